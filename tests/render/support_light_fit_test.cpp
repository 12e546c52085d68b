// The supports' regression stage of the denoiser: it takes the noise out of a thin rod's or
// wire's light along the support, whichever image axis it runs along, leaves short runs (a
// clip) and every other pixel as they are, and gives the same floats for any thread count.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "random_stream.hpp"
#include "denoise/support_light_fit.hpp"

namespace foldcast::render {
namespace support_light_fit_test {

constexpr int kW = 96, kH = 64;

// A backdrop with supports painted on it: each support pixel's normal turns with its offset
// across the support (a cylinder three pixels across), and its light, `light(along, across)`,
// changes much across the support and slowly along it, with Gaussian noise of `sigma`.  The
// guide is the clean luminance, taken to carry a variance of 1e-4 (the a-trous result).
struct Scene {
    std::vector<V3> clean, noisy;
    std::vector<float> guide, variance, fitted_variance, nx, ny, nz, depth, ax, ay, az, turning;
    std::vector<std::int32_t> support;
    SupportRegressionInput input() const {
        SupportRegressionInput in;
        in.width = kW, in.height = kH;
        in.light = &noisy, in.guide = &guide, in.variance = &variance, in.fitted_variance = &fitted_variance;
        in.nx = &nx, in.ny = &ny, in.nz = &nz, in.depth = &depth;
        in.ax = &ax, in.ay = &ay, in.az = &az, in.turning = &turning, in.support = &support;
        return in;
    }
    static std::size_t at(int x, int y) { return std::size_t(y) * kW + x; }
    Scene() {
        const std::size_t n = std::size_t(kW) * kH;
        clean.assign(n, V3::Constant(0.3f)), noisy = clean, guide.assign(n, 0.3f), variance.assign(n, 1e-4f);
        fitted_variance.assign(n, 0.0f), nx.assign(n, 0.0f), ny.assign(n, 0.0f), nz.assign(n, 1.0f);
        depth.assign(n, 4.0f), ax.assign(n, 0.7f), ay.assign(n, 0.7f), az.assign(n, 0.7f), turning.assign(n, 0.0f);
        support.assign(n, 0);
    }
    // A support pixel at offset `across` (-1, 0, 1) from the cylinder's axis, its normal turned
    // towards that side (along y for a rod, x for a wire).
    void paint(int x, int y, int across, bool rod, float light, float sigma, RandomStream& rng) {
        const std::size_t i = at(x, y);
        support[i] = 1, turning[i] = 1.0f, depth[i] = 3.0f;
        (rod ? ny : nx)[i] = 0.6f * float(across), nz[i] = across == 0 ? 1.0f : 0.8f;
        clean[i] = V3::Constant(light), guide[i] = light, fitted_variance[i] = sigma * sigma;
        const float u1 = std::max(1e-7f, rng.next()), u2 = rng.next();
        noisy[i] = V3::Constant(light + sigma * std::sqrt(-2.0f * std::log(u1)) * std::cos(6.2831853f * u2));
    }
};

// Across the cylinder the light goes from dark to a highlight; along it, it rises slowly.
float rod_light(int along, int across) {
    return (across < 0 ? 0.2f : across == 0 ? 0.9f : 0.5f) + 0.004f * float(along);
}

Scene rod_and_wire(float sigma) {
    Scene s;
    RandomStream rng(3, 5, 7);
    for (int x = 0; x < kW; ++x)
        for (int across = -1; across <= 1; ++across)
            s.paint(x, 20 + across, across, true, rod_light(x, across), sigma, rng);
    for (int y = 30; y < kH; ++y)
        for (int across = -1; across <= 1; ++across)
            s.paint(60 + across, y, across, false, rod_light(y, across), sigma, rng);
    return s;
}

// The RMSE over the pixels where `pick(x, y)`.
template <class Pick>
double rmse(const std::vector<V3>& a, const std::vector<V3>& b, Pick&& pick) {
    double sum = 0.0;
    int count = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            if (pick(x, y)) sum += double((a[Scene::at(x, y)] - b[Scene::at(x, y)]).squaredNorm()), count += 3;
    return std::sqrt(sum / count);
}

std::vector<V3> regressed(const Scene& s, std::vector<V3> out, int threads = 2) {
    tbb::task_arena arena(threads);
    arena.execute([&] { regress_supports(s.input(), out); });
    return out;
}

// Along the rod (rows) and along the wire (columns) the fit takes out more than half the noise
// (0.38 and 0.43 of it are left; the colour weight narrows the window where the light rises), though
// no two rows of the rod, nor two columns of the wire, are alike.
TEST(SupportRegression, TakesTheNoiseOutAlongTheSupport) {
    const Scene s = rod_and_wire(0.1f);
    const std::vector<V3> out = regressed(s, s.noisy);
    const auto rod = [](int x, int y) { return y >= 19 && y <= 21 && x >= 8 && x < kW - 8; };
    const auto wire = [](int x, int y) { return x >= 59 && x <= 61 && y >= 38 && y < kH - 8; };
    for (const auto& pick : {+rod, +wire}) {
        const double before = rmse(s.noisy, s.clean, pick), after = rmse(out, s.clean, pick);
        EXPECT_LT(after, 0.5 * before) << "before " << before << ", after " << after;
    }
}

// A support that runs on for fewer pixels than half the window (a clip) keeps what the passes
// made of it, and so does every pixel that is not a support.
TEST(SupportRegression, LeavesShortRunsAndOtherPixels) {
    Scene s;
    RandomStream rng(11, 13, 17);
    for (int y = 10; y < 20; ++y)
        for (int x = 40; x < 45; ++x) s.paint(x, y, 0, false, 0.4f, 0.1f, rng);
    for (std::size_t i = 0; i < s.noisy.size(); ++i)
        if (!s.support[i]) s.noisy[i] = V3::Constant(float(i % 7) * 0.1f);
    const std::vector<V3> out = regressed(s, s.noisy);
    for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i], s.noisy[i]) << "pixel " << i;
}

// A highlight's edge along the rod (the light jumps from 0.2 to 1.6 halfway): the pixels beside
// it stay within a few noise levels of the light instead of a fit spreading the step.
TEST(SupportRegression, KeepsAHighlightsEdge) {
    Scene s;
    RandomStream rng(5, 7, 9);
    for (int x = 0; x < kW; ++x) s.paint(x, 20, 0, true, x < kW / 2 ? 0.2f : 1.6f, 0.01f, rng);
    const std::vector<V3> out = regressed(s, s.clean);
    for (int x = kW / 2 - 3; x < kW / 2 + 3; ++x)
        EXPECT_NEAR(out[Scene::at(x, 20)].x(), s.clean[Scene::at(x, 20)].x(), 0.05f) << "x " << x;
}

// Where the light rises tenfold within a few pixels along the rod (a highlight's edge that
// the long quadratic cannot follow), the pixel gives way to a short line over its nearest
// taps along the rod rather than to what the passes kept (here the noisy light itself): the
// error there drops by a fifth or more (a line of sigma 0.7 px took off a quarter; sigma 1.4
// bends less at this sigmoid's shoulders, and the next test shows what it gains on a rise).
TEST(SupportRegression, GivesWayToAShortLineAtAHighlightsEdge) {
    Scene s;
    RandomStream rng(21, 23, 29);
    const auto light = [](int x) { return 0.15f + 1.35f / (1.0f + std::exp(-float(x - kW / 2) / 1.5f)); };
    for (int x = 0; x < kW; ++x)
        for (int across = -1; across <= 1; ++across) s.paint(x, 20 + across, across, true, light(x), 0.05f, rng);
    // The passes' result as guide is as noisy as the light there: a flat guide, so that the
    // colour weight does not narrow the long fit to the edge.
    for (int x = 0; x < kW; ++x)
        for (int y = 19; y <= 21; ++y) {
            s.guide[Scene::at(x, y)] = 0.8f;
            // What the stage fits is a quarter noisy light and three quarters the passes'
            // result: its noise is well below the light's.
            s.fitted_variance[Scene::at(x, y)] = 0.25f * 0.25f * 0.05f * 0.05f;
        }
    const std::vector<V3> out = regressed(s, s.noisy);
    const auto edge = [](int x, int y) { return y >= 19 && y <= 21 && std::abs(x - kW / 2) <= 4; };
    const double before = rmse(s.noisy, s.clean, edge), after = rmse(out, s.clean, edge);
    EXPECT_LT(after, 0.8 * before) << "before " << before << ", after " << after;
}

// Inside a highlight's steep rise (the light climbing tenfold, straight, over 8 pixels) the
// short line follows the rise and averages about four taps: the noise there drops by half or
// more (a line of sigma 0.7 px averaged three and left 0.55 of it).
TEST(SupportRegression, AveragesFourTapsInsideAHighlightsRise) {
    Scene s;
    RandomStream rng(31, 37, 41);
    const auto light = [](int x) { return 0.15f + 1.35f * std::clamp(float(x - kW / 2 + 4) / 8.0f, 0.0f, 1.0f); };
    for (int x = 0; x < kW; ++x)
        for (int across = -1; across <= 1; ++across) s.paint(x, 20 + across, across, true, light(x), 0.05f, rng);
    for (int x = 0; x < kW; ++x)
        for (int y = 19; y <= 21; ++y) s.guide[Scene::at(x, y)] = 0.8f, s.fitted_variance[Scene::at(x, y)] = 1e-6f;
    const std::vector<V3> out = regressed(s, s.noisy);
    const auto rise = [](int x, int y) { return y >= 19 && y <= 21 && std::abs(x - kW / 2) <= 2; };
    const double before = rmse(s.noisy, s.clean, rise), after = rmse(out, s.clean, rise);
    EXPECT_LT(after, 0.5 * before) << "before " << before << ", after " << after;
}

TEST(SupportRegression, SameFloatsForAnyThreadCount) {
    const Scene s = rod_and_wire(0.1f);
    const std::vector<V3> one = regressed(s, s.noisy, 1), three = regressed(s, s.noisy, 3);
    EXPECT_EQ(0, std::memcmp(one.data(), three.data(), one.size() * sizeof(V3)));
}

}  // namespace support_light_fit_test
}  // namespace foldcast::render
