// The denoiser: it removes noise from smooth light, keeps texture that lives in the albedo
// and edges that show in the normals, leaves uncovered pixels alone, and gives the same
// result for any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "denoise/denoise.hpp"
#include "random_stream.hpp"

namespace foldcast::render {
namespace denoise_test {

constexpr int kW = 64, kH = 48;

struct Scene {
    Image noisy, clean;
    PixelFeatures features;
};

// A plane lit by a smooth gradient, with a checkerboard albedo of 2-pixel squares (a
// "weave"), its left and right halves facing different ways (a fold edge), and noise of a
// known variance on the light.
Scene make_scene(float sigma) {
    Scene s;
    s.noisy = s.clean = Image{kW, kH, 4, std::vector<float>(kW * kH * 4, 1.0f)};
    const std::size_t n = static_cast<std::size_t>(kW) * kH;
    s.features.albedo.resize(n);
    s.features.normal.resize(n);
    s.features.depth.assign(n, 2.0f);
    s.features.variance.assign(n, sigma * sigma);
    RandomStream rng(1, 2, 3);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * kW + x;
            const bool left = x < kW / 2;
            const float light = (left ? 0.8f : 0.3f) + 0.2f * static_cast<float>(y) / kH;
            const float albedo = ((x / 2 + y / 2) % 2 == 0) ? 0.7f : 0.3f;
            s.features.albedo[i] = V3::Constant(albedo);
            s.features.normal[i] = left ? V3(0.0f, 0.0f, 1.0f) : V3(0.8f, 0.0f, 0.6f);
            // Gaussian noise by Box-Muller.
            const float u1 = std::max(1e-7f, rng.next()), u2 = rng.next();
            const float g = std::sqrt(-2.0f * std::log(u1)) * std::cos(6.2831853f * u2);
            for (int c = 0; c < 3; ++c) {
                s.clean.at(x, y)[c] = light * albedo;
                s.noisy.at(x, y)[c] = (light + sigma * g) * albedo;
            }
        }
    return s;
}

double rmse(const Image& a, const Image& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        if (i % 4 != 3) sum += (a.pixels[i] - b.pixels[i]) * double(a.pixels[i] - b.pixels[i]);
    return std::sqrt(sum / (a.pixels.size() * 3 / 4));
}

// The scene denoised (two threads), its error against the clean image under 0.3 of the
// noisy one's.
Image denoised_with_less_noise(const Scene& s) {
    const double before = rmse(s.noisy, s.clean);
    Image out = s.noisy;
    denoise(out, s.features, 2, DenoiseBudget::still);
    const double after = rmse(out, s.clean);
    EXPECT_LT(after, 0.3 * before) << "before " << before << ", after " << after;
    return out;
}

// The fold edge stays sharp: the columns either side of it keep their own light.
void expect_fold_edge_kept(const Image& out, const Scene& s) {
    for (int y = 4; y < kH - 4; ++y) {
        const float l = out.at(kW / 2 - 1, y)[0] / s.features.albedo[y * kW + kW / 2 - 1].x();
        const float r = out.at(kW / 2, y)[0] / s.features.albedo[y * kW + kW / 2].x();
        EXPECT_GT(l - r, 0.35f) << "row " << y;
    }
}

TEST(Denoise, RemovesNoiseAndKeepsTheWeaveAndTheFold) {
    const Scene s = make_scene(0.1f);
    const Image out = denoised_with_less_noise(s);
    // The checkerboard survives: neighbouring squares keep their albedo contrast.
    double contrast = 0.0;
    for (int y = 4; y < kH - 4; ++y)
        for (int x = 4; x < kW / 2 - 4; x += 2)
            contrast += std::abs(out.at(x, y)[0] - out.at(x + 2, y)[0]) / ((kH - 8) * (kW / 4 - 4));
    EXPECT_GT(contrast, 0.8 * 0.8 * 0.4) << "the weave was blurred";  // light ~0.9 x albedo step 0.4
    expect_fold_edge_kept(out, s);
}

TEST(Denoise, LeavesUncoveredPixelsAndAlphaAlone) {
    Scene s = make_scene(0.1f);
    for (int y = 0; y < kH; ++y) s.noisy.at(5, y)[3] = 0.0f;
    for (int y = 0; y < kH; ++y) s.noisy.at(5, y)[0] = 123.0f;  // would smear if used
    Image out = s.noisy;
    denoise(out, s.features, 1, DenoiseBudget::still);
    for (int y = 0; y < kH; ++y) {
        EXPECT_EQ(out.at(5, y)[0], 123.0f);
        EXPECT_EQ(out.at(5, y)[3], 0.0f);
        EXPECT_LT(out.at(4, y)[0], 2.0f);
    }
}

// The scene denoised on one thread and on three gives the same bits.
void expect_same_for_any_thread_count(const Scene& s) {
    Image a = s.noisy, b = s.noisy;
    denoise(a, s.features, 1, DenoiseBudget::still);
    denoise(b, s.features, 3, DenoiseBudget::still);
    EXPECT_EQ(0, std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)));
}

TEST(Denoise, SameResultForAnyThreadCount) { expect_same_for_any_thread_count(make_scene(0.2f)); }

// Two half buffers, each with its own noise (twice the variance of their mean), and the
// image their mean: the denoiser cross-filters them.
Scene with_halves(float sigma) {
    Scene s = make_scene(sigma * std::sqrt(2.0f));
    const Scene other = [&] {
        Scene o = make_scene(sigma * std::sqrt(2.0f));
        RandomStream rng(4, 5, 6);  // other noise on the same light
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const float u1 = std::max(1e-7f, rng.next()), u2 = rng.next();
                const float g = std::sqrt(-2.0f * std::log(u1)) * std::cos(6.2831853f * u2);
                const float albedo = o.features.albedo[static_cast<std::size_t>(y) * kW + x].x();
                for (int c = 0; c < 3; ++c)
                    o.noisy.at(x, y)[c] = o.clean.at(x, y)[c] + sigma * std::sqrt(2.0f) * g * albedo;
            }
        return o;
    }();
    const std::size_t n = static_cast<std::size_t>(kW) * kH;
    s.features.half_a.resize(n);
    s.features.half_b.resize(n);
    s.features.half_share.assign(n, 0.5f);
    s.features.variance.assign(n, sigma * sigma);
    for (std::size_t i = 0; i < n; ++i) {
        float* c = &s.noisy.pixels[4 * i];
        const float* d = &other.noisy.pixels[4 * i];
        for (int k = 0; k < 3; ++k) {
            s.features.half_a[i][k] = c[k];
            s.features.half_b[i][k] = d[k];
            c[k] = 0.5f * (c[k] + d[k]);
        }
    }
    return s;
}

TEST(Denoise, CrossFiltersTwoHalvesAndKeepsTheFold) {
    const Scene s = with_halves(0.1f);
    expect_fold_edge_kept(denoised_with_less_noise(s), s);
}

TEST(Denoise, CrossFilteringIsTheSameForAnyThreadCount) { expect_same_for_any_thread_count(with_halves(0.2f)); }

// A thin wire in front of the backdrop (make_scene's left half): its column's pixels are
// partly wire (half their samples on it, so brighter), the rest plain backdrop, at the same
// depth and normal (the features of a mixed pixel lean towards the backdrop's).  The wire's pixels must stay
// bright: the share of samples on the garment and supports tells them apart, where depth,
// normal and (noisy) light do not.  Without the mixture weight the column is averaged with
// the backdrop beside it.
TEST(Denoise, AThinWiresPartlyCoveredPixelsAreNotAveragedWithTheBackdrop) {
    Scene s = make_scene(0.1f);
    const std::size_t n = static_cast<std::size_t>(kW) * kH;
    s.features.turning.assign(n, 0.0f);
    const int wire = kW / 4;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * kW + x;
            if (x != wire) continue;
            s.features.turning[i] = 0.5f;
            for (int c = 0; c < 3; ++c) {  // half again as much light as the backdrop beside it
                s.clean.at(x, y)[c] *= 1.5f;
                s.noisy.at(x, y)[c] *= 1.5f;
            }
        }
    Image out = s.noisy;
    denoise(out, s.features, 2, DenoiseBudget::still);
    double lost = 0.0;  // of the wire's extra light, on average over the column
    for (int y = 4; y < kH - 4; ++y) {
        const float clean = s.clean.at(wire, y)[0], backdrop = clean / 1.5f;
        lost += (clean - out.at(wire, y)[0]) / (clean - backdrop);
    }
    lost /= kH - 8;
    EXPECT_LT(std::abs(lost), 0.2) << "the wire's pixels lost " << lost << " of their extra light";
}

// Cloth whose dark green albedo rises smoothly through the demodulation floor (velvet's
// green channel as its sheen rises with the view angle), under smooth light with little
// noise: the denoised green follows the input's, with no line where the albedo crosses
// the floor (a divisor that jumped there drew bright contour lines on the velvet swatch).
TEST(Denoise, AnAlbedoCrossingTheDemodulationFloorLeavesNoLine) {
    Image noisy{kW, kH, 4, std::vector<float>(kW * kH * 4, 1.0f)};
    PixelFeatures f;
    const std::size_t n = static_cast<std::size_t>(kW) * kH;
    f.albedo.resize(n), f.normal.assign(n, V3(0.0f, 0.0f, 1.0f)), f.depth.assign(n, 2.0f);
    f.variance.assign(n, 1e-6f), f.cloth.assign(n, 1.0f), f.turning.assign(n, 1.0f);
    RandomStream rng(3, 5, 7);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * kW + x;
            const float green = 0.004f + 0.012f * static_cast<float>(x) / (kW - 1);  // 0.004-0.016
            f.albedo[i] = V3(0.3f, green, 0.2f);
            const float light = 0.6f * (1.0f + 0.01f * (rng.next() - 0.5f));
            for (int c = 0; c < 3; ++c) noisy.at(x, y)[c] = light * f.albedo[i][c];
        }
    Image out = noisy;
    denoise(out, f, 2, DenoiseBudget::still);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            EXPECT_NEAR(out.at(x, y)[1] / noisy.at(x, y)[1], 1.0f, 0.05f) << "x " << x << ", y " << y;
}

}  // namespace denoise_test
}  // namespace foldcast::render
