// The silhouette's blend, a still's last denoising step: it takes the noise out of pixels
// partly garment and partly backdrop, leaves a pixel whose neighbours differ by more than
// its noise explains, and touches no other pixel.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "random_stream.hpp"
#include "silhouette_blend.hpp"

namespace foldcast::render {
namespace {

constexpr int kW = 24, kH = 20;

struct Frame {
    std::vector<float> rgba, cloth, turning, variance;
    std::vector<std::int32_t> covered;
    explicit Frame(float share, float variance_value)
        : rgba(std::size_t(4) * kW * kH, 1.0f),
          cloth(std::size_t(kW) * kH, share),
          turning(std::size_t(kW) * kH, share),
          variance(std::size_t(kW) * kH, variance_value),
          covered(std::size_t(kW) * kH, 1) {}
    SilhouetteInput input() const {
        SilhouetteInput in;
        in.width = kW, in.height = kH;
        in.cloth = &cloth, in.turning = &turning, in.variance = &variance, in.covered = &covered;
        return in;
    }
    void grey(std::size_t i, float v) { rgba[4 * i] = rgba[4 * i + 1] = rgba[4 * i + 2] = v; }
};

// A silhouette half garment, half backdrop, whose light is 0.5 under a noise of 0.1 (the
// pixels' variance 0.01): the noise inside the border falls by more than a sixth (a pixel
// whose difference from its neighbours is a noise's, about 0.1, moves half of it).
TEST(SilhouetteBlend, TakesTheNoiseOutOfMixedPixels) {
    Frame f(0.5f, 0.01f);
    RandomStream rng(3, 5, 7);
    for (std::size_t i = 0; i < f.cloth.size(); ++i) {
        const float u1 = std::max(1e-7f, rng.next()), u2 = rng.next();
        f.grey(i, 0.5f + 0.1f * std::sqrt(-2.0f * std::log(u1)) * std::cos(6.2831853f * u2));
    }
    const std::vector<float> noisy = f.rgba;
    blend_silhouette(f.input(), f.rgba);
    double before = 0.0, after = 0.0;
    for (int y = 1; y + 1 < kH; ++y)
        for (int x = 1; x + 1 < kW; ++x) {
            const std::size_t i = std::size_t(y) * kW + x;
            before += (noisy[4 * i] - 0.5) * (noisy[4 * i] - 0.5);
            after += (f.rgba[4 * i] - 0.5) * (f.rgba[4 * i] - 0.5);
        }
    // (RMS 0.098 -> 0.076 when written)
    EXPECT_LT(std::sqrt(after), 0.85 * std::sqrt(before)) << before << " -> " << after;
}

// A mixed pixel of little noise between neighbours far brighter: the difference is not its
// noise, and it keeps its light.
TEST(SilhouetteBlend, KeepsAPixelItsNoiseDoesNotExplain) {
    Frame f(0.5f, 1e-6f);
    for (std::size_t i = 0; i < f.cloth.size(); ++i) f.grey(i, 0.8f);
    const std::size_t centre = std::size_t(kH / 2) * kW + kW / 2;
    f.grey(centre, 0.4f);
    blend_silhouette(f.input(), f.rgba);
    EXPECT_NEAR(f.rgba[4 * centre], 0.4f, 0.001f);
}

// Pixels wholly garment or backdrop, or partly the rod or a wire, and every alpha keep
// their bytes; a mixed pixel among them with too few neighbours of its share stays too.
TEST(SilhouetteBlend, LeavesEveryOtherPixelAlone) {
    Frame f(1.0f, 0.01f);
    RandomStream rng(11, 13, 17);
    for (std::size_t i = 0; i < f.cloth.size(); ++i) {
        f.grey(i, rng.next());
        f.rgba[4 * i + 3] = 0.5f + 0.5f * rng.next();
        if (i % 3 == 0) f.cloth[i] = f.turning[i] = 0.0f;        // backdrop
        if (i % 7 == 0) f.cloth[i] = 0.4f, f.turning[i] = 0.9f;  // partly a wire
    }
    const std::vector<float> before = f.rgba;
    blend_silhouette(f.input(), f.rgba);
    EXPECT_EQ(std::memcmp(before.data(), f.rgba.data(), before.size() * sizeof(float)), 0);
}

}  // namespace
}  // namespace foldcast::render
