// The backdrop's regression stage of the denoiser: it takes the noise out of light that is
// smooth in the position and the depth, keeps a shadow's edge that the model cannot follow,
// reads and writes nothing but backdrop pixels, and gives the same floats for any thread
// count.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>

#include "denoise/backdrop_light_fit.hpp"
#include "random_stream.hpp"

namespace foldcast::render {
namespace backdrop_light_fit_test {

constexpr int kW = 64, kH = 48;

// A backdrop whose lower half bends away from the camera (the floor: the depth grows by
// row), its light `light(x, y, depth)` with Gaussian noise of `sigma`.  The guide is the
// clean luminance, taken to carry a variance of 1e-4 (the a-trous result it stands for).
struct Backdrop {
    std::vector<V3> clean, noisy;
    std::vector<float> guide, variance, depth;
    std::vector<std::int32_t> backdrop;
    BackdropRegressionInput input() const {
        BackdropRegressionInput in;
        in.width = kW, in.height = kH;
        in.light = &noisy, in.guide = &guide, in.variance = &variance, in.depth = &depth, in.backdrop = &backdrop;
        return in;
    }
};

template <class Light>
Backdrop make_backdrop(float sigma, Light&& light) {
    Backdrop b;
    const std::size_t n = std::size_t(kW) * kH;
    b.clean.resize(n), b.noisy.resize(n), b.guide.resize(n), b.variance.assign(n, 1e-4f), b.depth.resize(n);
    b.backdrop.assign(n, 1);
    RandomStream rng(3, 5, 7);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const std::size_t i = std::size_t(y) * kW + x;
            b.depth[i] = 4.0f + (y > kH / 2 ? 0.008f * float((y - kH / 2) * (y - kH / 2)) : 0.0f);
            const float l = light(x, y, b.depth[i]);
            b.clean[i] = V3::Constant(l);
            b.guide[i] = l;
            const float u1 = std::max(1e-7f, rng.next()), u2 = rng.next();
            b.noisy[i] = V3::Constant(l + sigma * std::sqrt(-2.0f * std::log(u1)) * std::cos(6.2831853f * u2));
        }
    return b;
}

double rmse(const std::vector<V3>& a, const std::vector<V3>& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) sum += double((a[i] - b[i]).squaredNorm());
    return std::sqrt(sum / (3.0 * a.size()));
}

std::vector<V3> regressed(const Backdrop& b, std::vector<V3> out, int threads = 2) {
    tbb::task_arena arena(threads);
    arena.execute([&] { regress_backdrop(b.input(), out); });
    return out;
}

// Light that changes across the image and with the floor's depth (not linear in the row
// there): the fit in the position and the depth takes out nine tenths of the noise (0.0094
// of 0.1 left); a fit in the position alone leaves 0.013.
TEST(BackdropRegression, TakesTheNoiseOutOfSmoothLight) {
    const Backdrop b = make_backdrop(0.1f, [](int x, int y, float depth) {
        return 0.3f + 0.002f * float(x) + 0.001f * float(y) + 0.1f * (depth - 4.0f);
    });
    const double before = rmse(b.noisy, b.clean), after = rmse(regressed(b, b.noisy), b.clean);
    EXPECT_LT(after, 0.11 * before) << "before " << before << ", after " << after;
}

// A shadow's edge across the backdrop: the pixels beside it keep the passes' result (here
// the clean light) instead of a fit that spreads the step over the window.
TEST(BackdropRegression, KeepsAShadowsEdge) {
    const Backdrop b = make_backdrop(0.05f, [](int x, int, float) { return x < kW / 2 ? 0.6f : 0.2f; });
    const std::vector<V3> out = regressed(b, b.clean);
    for (int y = 0; y < kH; ++y)
        for (int x = kW / 2 - 3; x < kW / 2 + 3; ++x) {
            const std::size_t i = std::size_t(y) * kW + x;
            EXPECT_NEAR(out[i].x(), b.clean[i].x(), 0.02f) << "x " << x << ", y " << y;
        }
}

// Pixels that are not backdrop (the garment, the rod) keep their light, and their light
// does not reach the backdrop's fit.
TEST(BackdropRegression, TouchesNothingButTheBackdrop) {
    Backdrop b = make_backdrop(0.1f, [](int, int, float) { return 0.5f; });
    for (int y = 10; y < 30; ++y)
        for (int x = 20; x < 40; ++x) b.backdrop[std::size_t(y) * kW + x] = 0;
    const std::vector<V3> first = regressed(b, b.noisy);
    Backdrop other = b;
    for (std::size_t i = 0; i < other.noisy.size(); ++i)
        if (!other.backdrop[i]) other.noisy[i] = V3::Constant(9.0f), other.guide[i] = 9.0f;
    const std::vector<V3> second = regressed(other, other.noisy);
    for (std::size_t i = 0; i < first.size(); ++i) {
        if (b.backdrop[i])
            EXPECT_EQ(first[i], second[i]) << "pixel " << i;
        else
            EXPECT_EQ(first[i], b.noisy[i]) << "pixel " << i;
    }
}

TEST(BackdropRegression, SameFloatsForAnyThreadCount) {
    const Backdrop b =
        make_backdrop(0.1f, [](int x, int y, float) { return 0.3f + 0.01f * float(x % 7) + 0.002f * float(y); });
    const std::vector<V3> one = regressed(b, b.noisy, 1), two = regressed(b, b.noisy, 2);
    EXPECT_EQ(0, std::memcmp(one.data(), two.data(), one.size() * sizeof(V3)));
}

}  // namespace backdrop_light_fit_test
}  // namespace foldcast::render
