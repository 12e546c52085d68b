// The cloth's regression stage of the denoiser: it follows shading that changes with the
// normal faster than the a-trous passes' normal weight lets them average, keeps apart cloth
// of different colours and the two sides of a shadow's edge, touches nothing but cloth, and
// gives the same floats for any thread count.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>

#include "denoise/cloth_light_fit.hpp"
#include "random_stream.hpp"

namespace foldcast::render {
namespace cloth_light_fit_test {

// 50 columns: the 4-wide path does not fit the row exactly, so pixels with their whole
// window inside the image are fitted by both paths.
constexpr int kW = 50, kH = 32;

struct Plane {
    std::vector<V3> clean, noisy;
    std::vector<float> guide, variance, noise, nx, ny, nz, depth, ax, ay, az;
    std::vector<std::int32_t> cloth;
    bool depth_regressor = false;  // a still's regression
    bool average_fits = false;     // a still's, its fits averaged over the window
    float spatial_sigma = 3.0f;
    ClothRegressionInput input() const {
        ClothRegressionInput in;
        in.width = kW, in.height = kH;
        in.light = &noisy, in.guide = &guide, in.variance = &variance, in.fitted_variance = &noise;
        in.nx = &nx, in.ny = &ny, in.nz = &nz, in.depth = &depth;
        in.ax = &ax, in.ay = &ay, in.az = &az, in.cloth = &cloth;
        in.depth_regressor = depth_regressor, in.average_fits = average_fits;
        in.spatial_sigma = spatial_sigma;
        return in;
    }
};

// Cloth at 2 m whose normal is `normal_angle(x)` radians about the vertical, lit so that
// its light is `light(x, y, normal)`, with Gaussian noise of `sigma`.  The guide is the clean
// luminance, taken to carry a noise of 0.03 (the a-trous result it stands for does).
template <class Angle, class Light>
Plane make_plane(Angle&& normal_angle, float sigma, Light&& light) {
    Plane p;
    const std::size_t n = std::size_t(kW) * kH;
    p.clean.resize(n), p.noisy.resize(n), p.guide.resize(n), p.variance.assign(n, 1e-3f);
    p.noise.assign(n, sigma * sigma);
    p.nx.resize(n), p.ny.assign(n, 0.0f), p.nz.resize(n), p.depth.assign(n, 2.0f);
    p.ax.assign(n, 0.5f), p.ay.assign(n, 0.5f), p.az.assign(n, 0.5f), p.cloth.assign(n, 1);
    RandomStream rng(7, 11, 13);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const std::size_t i = std::size_t(y) * kW + x;
            const float angle = normal_angle(x);
            p.nx[i] = std::sin(angle), p.nz[i] = std::cos(angle);
            const float l = light(x, y, V3(p.nx[i], 0.0f, p.nz[i]));
            p.clean[i] = V3::Constant(l);
            p.guide[i] = l;
            const float u1 = std::max(1e-7f, rng.next()), u2 = rng.next();
            const float g = std::sqrt(-2.0f * std::log(u1)) * std::cos(6.2831853f * u2);
            p.noisy[i] = V3::Constant(l + sigma * g);
        }
    return p;
}
// Flat cloth facing the camera.
float flat(int) { return 0.0f; }

double rmse(const std::vector<V3>& a, const std::vector<V3>& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) sum += double((a[i] - b[i]).squaredNorm());
    return std::sqrt(sum / (3.0 * a.size()));
}

std::vector<V3> regressed(const Plane& p, int threads = 2) {
    std::vector<V3> out = p.noisy;
    tbb::task_arena arena(threads);
    arena.execute([&] { regress_cloth(p.input(), out); });
    return out;
}

// Wrinkles 6 pixels apart, the normal swinging 0.5 rad either way (cos^128 between
// neighbours down to 0.01): the light, linear in the normal but not in the position, is
// recovered from its noise.  A fit in the position alone leaves 0.06 of the
// noise's 0.1 here; this one 0.026.
TEST(ClothRegression, FollowsShadingThatChangesWithTheNormal) {
    const auto wrinkles = [](int x) { return 0.5f * std::sin(6.2831853f * float(x) / 6.0f); };
    const Plane p = make_plane(wrinkles, 0.1f, [&](int, int, const V3& n) { return 0.3f + 0.5f * n.x(); });
    const double before = rmse(p.noisy, p.clean), after = rmse(regressed(p), p.clean);
    EXPECT_LT(after, 0.3 * before) << "before " << before << ", after " << after;
}

// Flat cloth facing the camera whose depth waves (a fold running away from the lens) and
// whose light follows the depth: a fit in the normal and the position cannot follow a wave
// of 13 pixels within a 9 x 9 window, a still's fit with the depth's change does.
TEST(ClothRegression, StillsFollowLightThatChangesWithTheDepth) {
    Plane p = make_plane(flat, 0.05f, [](int x, int, const V3&) { return 0.5f + 0.3f * std::sin(float(x) / 2.0f); });
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) p.depth[std::size_t(y) * kW + x] = 2.0f + 0.01f * std::sin(float(x) / 2.0f);
    const double before = rmse(p.noisy, p.clean), frame = rmse(regressed(p), p.clean);
    p.depth_regressor = true;
    const double still = rmse(regressed(p), p.clean);
    // (noise 0.05, frame 0.035, still 0.012 when written)
    EXPECT_LT(still, 0.5 * frame) << "noise " << before << ", frame " << frame << ", still " << still;
}

// Folds of 16 pixels on flat-lit cloth whose light bends within the window (a garment seen
// small): the narrower window of a small garment's still follows them where sigma 3 smooths
// them away.
TEST(ClothRegression, ANarrowerWindowFollowsFinerFolds) {
    Plane p = make_plane(flat, 0.05f, [](int x, int, const V3&) { return 0.5f + 0.3f * std::sin(float(x) / 2.5f); });
    const double wide = rmse(regressed(p), p.clean);
    p.spatial_sigma = 1.5f;
    const double narrow = rmse(regressed(p), p.clean);
    // (0.041 and 0.027 when written)
    EXPECT_LT(narrow, 0.8 * wide) << "sigma 3: " << wide << ", sigma 1.5: " << narrow;
}

// A still's small window (a garment seen small) on wrinkles: each pixel's own fit keeps much
// of the noise, the mean of the overlapping windows' fits evaluated at the pixel less.
TEST(ClothRegression, StillsAveragingTheFitsLowersTheirNoise) {
    const auto wrinkles = [](int x) { return 0.5f * std::sin(6.2831853f * float(x) / 8.0f); };
    Plane p = make_plane(wrinkles, 0.1f, [](int, int y, const V3& n) { return 0.3f + 0.5f * n.x() + 0.005f * y; });
    p.depth_regressor = true, p.spatial_sigma = 1.5f;
    const double own = rmse(regressed(p), p.clean);
    p.average_fits = true;
    const double averaged = rmse(regressed(p), p.clean);
    // (noise 0.1, own fit 0.0386, averaged 0.0356 when written)
    EXPECT_LT(averaged, 0.95 * own) << "own fit " << own << ", averaged " << averaged;
}

// A glossy sheen lobe on wrinkles (light far from linear in the normal near its crest) under
// noise the fits still pass: a neighbour's fit extrapolated to a crest pixel misses the crest,
// so the mean backs off from the neighbours whose value there disagrees with the pixel's own
// fit.  (Crests' mean error when written: own fit -0.015, averaged -0.017, the plain mean of
// the fits -0.031; the whole image's RMSE 0.0296 / 0.0280 / 0.0301.)
TEST(ClothRegression, AveragedFitsBackOffWhereTheyDisagree) {
    const auto wrinkles = [](int x) { return 0.5f * std::sin(6.2831853f * float(x) / 10.0f); };
    Plane p = make_plane(wrinkles, 0.05f, [](int, int, const V3& n) {
        const float lobe = std::max(0.0f, n.x() - 0.25f);
        return 0.2f + 6.0f * lobe * lobe;
    });
    p.depth_regressor = true, p.spatial_sigma = 1.5f;
    const std::vector<V3> own = regressed(p);
    p.average_fits = true;
    const std::vector<V3> averaged = regressed(p);
    double crest_bias = 0.0;
    int crests = 0;
    for (std::size_t i = 0; i < averaged.size(); ++i)
        if (p.clean[i].x() >= 0.3f) crest_bias += double(averaged[i].x() - p.clean[i].x()), ++crests;
    ASSERT_GT(crests, 0);
    crest_bias /= crests;
    EXPECT_LT(std::abs(crest_bias), 0.022) << "the crests' mean error";
    EXPECT_LT(rmse(averaged, p.clean), rmse(own, p.clean));
}

// With own_fits, the regression also writes each pixel's own fit: the floats of the same
// regression without the averaging (the halves' blend chooses between the two).
TEST(ClothRegression, StillsWriteTheOwnFitsBesideTheAveraged) {
    const auto wrinkles = [](int x) { return 0.5f * std::sin(6.2831853f * float(x) / 8.0f); };
    Plane p = make_plane(wrinkles, 0.1f, [](int, int y, const V3& n) { return 0.3f + 0.5f * n.x() + 0.005f * y; });
    p.depth_regressor = true, p.spatial_sigma = 1.5f;
    const std::vector<V3> alone = regressed(p);
    std::vector<V3> out = p.noisy, own = p.noisy;
    ClothRegressionInput in = p.input();
    in.average_fits = true, in.own_fits = &own;
    tbb::task_arena arena(2);
    arena.execute([&] { regress_cloth(in, out); });
    EXPECT_EQ(std::memcmp(own.data(), alone.data(), own.size() * sizeof(V3)), 0);
    EXPECT_NE(std::memcmp(out.data(), alone.data(), out.size() * sizeof(V3)), 0);
}

// Light linear in the normal and the position, without noise: every neighbour's fit is the
// light itself, so their mean at the pixel is too (the regressors are evaluated about the
// neighbour, not the pixel).
TEST(ClothRegression, AveragedFitsKeepLightTheModelHolds) {
    const auto wrinkles = [](int x) { return 0.4f * std::sin(6.2831853f * float(x) / 10.0f); };
    Plane p = make_plane(wrinkles, 0.0f, [](int x, int y, const V3& n) {
        return 0.3f + 0.4f * n.x() + 0.2f * n.z() + 0.004f * float(x + y);
    });
    p.noise.assign(p.noise.size(), 1e-4f);
    p.depth_regressor = true, p.average_fits = true, p.spatial_sigma = 1.5f;
    const std::vector<V3> out = regressed(p);
    for (std::size_t i = 0; i < out.size(); ++i) EXPECT_NEAR(out[i].x(), p.clean[i].x(), 2e-3f) << i;
}

// Creases in flat-lit cloth (shadowed troughs about 3 pixels wide, the normal not turning
// with them: the light is occluded, not shaded): a plane fitted across a trough's bottom
// comes out too bright there, a still's fit with the offset's squares follows it closer.
TEST(ClothRegression, StillsFollowACreasesTroughToItsBottom) {
    const auto trough = [](int x) {
        const float d = float((x % 13) - 6);
        return 0.3f - 0.2f * std::exp(-d * d / 4.5f);
    };
    Plane p = make_plane(flat, 0.05f, [&](int x, int, const V3&) { return trough(x); });
    p.depth_regressor = true, p.average_fits = true, p.spatial_sigma = 1.5f;
    // The guide as noisy as the passes leave a trough's: the colour weight lets the shoulders in.
    p.variance.assign(p.variance.size(), 1e-2f);
    const std::vector<V3> out = regressed(p);
    double bias = 0.0;
    int bottoms = 0;
    for (int y = 4; y < kH - 4; ++y)
        for (int x = 6; x < kW - 4; x += 13, ++bottoms) {
            const std::size_t i = std::size_t(y) * kW + x;
            bias += double(out[i].x() - p.clean[i].x());
        }
    bias /= bottoms;
    // (light 0.1 at the bottom; 0.043 too bright with the plane, 0.026 with the squares when
    // written)
    EXPECT_LT(std::abs(bias), 0.033) << "the bottom's mean error " << bias;
}

// The window follows the garment's size in pixels: 1.5 at the default scene's 320x180 (about
// 4 500 cloth pixels), 3 from its 640x360 (about 18 000) on, in between by the square root.
TEST(ClothRegression, AStillsWindowFollowsTheGarmentsSize) {
    EXPECT_FLOAT_EQ(still_spatial_sigma(0), 1.5f);
    EXPECT_NEAR(still_spatial_sigma(4482), 1.5f, 0.05f);
    EXPECT_NEAR(still_spatial_sigma(18084), 3.0f, 1e-6f);
    EXPECT_FLOAT_EQ(still_spatial_sigma(72708), 3.0f);
    EXPECT_NEAR(still_spatial_sigma(9000), 2.16f, 0.02f);
}

// A glossy highlight across the wrinkles (light far from linear in the normal) under little
// noise: the fit cannot follow it, and the pixels keep what the passes made of them.
TEST(ClothRegression, LeavesAHighlightItCannotFitToThePasses) {
    const auto wrinkles = [](int x) { return 0.5f * std::sin(6.2831853f * float(x) / 12.0f); };
    Plane p = make_plane(wrinkles, 0.005f, [](int, int, const V3& n) {
        const float lobe = std::max(0.0f, n.x() - 0.3f);
        return 0.2f + 40.0f * lobe * lobe;
    });
    p.variance.assign(p.variance.size(), 0.05f);  // a guide too noisy to keep the crest apart
    std::vector<V3> out = p.clean;                // the passes' result stands in: the clean light
    tbb::task_arena arena(2);
    arena.execute([&] { regress_cloth(p.input(), out); });
    int peaks = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const std::size_t i = std::size_t(y) * kW + x;
            if (p.clean[i].x() < 0.8f) continue;  // the highlight's crest
            ++peaks;
            EXPECT_NEAR(out[i].x(), p.clean[i].x(), 0.02f * p.clean[i].x()) << "x " << x << ", y " << y;
        }
    EXPECT_GT(peaks, 0);
}

// Two colours of one cloth (a printed stripe, its own albedo and light): the stripe's edge
// columns keep their own light, not the mean of both.
TEST(ClothRegression, KeepsClothOfAnotherColourApart) {
    Plane p = make_plane(flat, 0.02f, [](int x, int, const V3&) { return x < kW / 2 ? 0.8f : 0.3f; });
    for (int y = 0; y < kH; ++y)
        for (int x = kW / 2; x < kW; ++x) {
            const std::size_t i = std::size_t(y) * kW + x;
            p.ax[i] = 0.2f, p.ay[i] = 0.3f, p.az[i] = 0.6f;
            p.guide[i] = 0.5f;  // a guide that does not tell them apart: only the albedo does
        }
    for (std::size_t i = 0; i < p.guide.size(); ++i) p.guide[i] = 0.5f;
    const std::vector<V3> out = regressed(p);
    for (int y = 2; y < kH - 2; ++y) {
        EXPECT_NEAR(out[std::size_t(y) * kW + kW / 2 - 1].x(), 0.8f, 0.05f) << "row " << y;
        EXPECT_NEAR(out[std::size_t(y) * kW + kW / 2].x(), 0.3f, 0.05f) << "row " << y;
    }
}

// A shadow's edge across flat cloth of one colour: the guide's luminance keeps its sides apart.
TEST(ClothRegression, KeepsAShadowEdge) {
    const Plane p = make_plane(flat, 0.02f, [](int, int y, const V3&) { return y < kH / 2 ? 0.8f : 0.1f; });
    const std::vector<V3> out = regressed(p);
    for (int x = 2; x < kW - 2; ++x) {
        EXPECT_NEAR(out[std::size_t(kH / 2 - 1) * kW + x].x(), 0.8f, 0.06f) << "column " << x;
        EXPECT_NEAR(out[std::size_t(kH / 2) * kW + x].x(), 0.1f, 0.06f) << "column " << x;
    }
}

// Pixels that are not cloth keep what the output held, bit for bit.
TEST(ClothRegression, LeavesPixelsThatAreNotClothAlone) {
    Plane p = make_plane([](int x) { return 0.05f * float(x - kW / 2); }, 0.1f,
                         [](int, int, const V3& n) { return 0.5f + 0.3f * n.x(); });
    for (std::size_t i = 0; i < p.cloth.size(); i += 3) p.cloth[i] = 0;
    std::vector<V3> out(p.noisy.size(), V3(-1.0f, -2.0f, -3.0f));
    tbb::task_arena arena(2);
    arena.execute([&] { regress_cloth(p.input(), out); });
    for (std::size_t i = 0; i < out.size(); ++i) {
        if (p.cloth[i]) {
            EXPECT_GE(out[i].minCoeff(), 0.0f) << i;
        } else {
            EXPECT_EQ(out[i], V3(-1.0f, -2.0f, -3.0f)) << i;
        }
    }
}

TEST(ClothRegression, SameFloatsForAnyThreadCount) {
    const Plane p = make_plane([](int x) { return 0.1f * float(x - kW / 2); }, 0.1f,
                               [](int x, int y, const V3& n) { return 0.3f + 0.4f * n.z() + 0.001f * float(x * y); });
    const std::vector<V3> one = regressed(p, 1), two = regressed(p, 2);
    ASSERT_EQ(one.size(), two.size());
    EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(V3)), 0);
}

TEST(ClothRegression, StillsAveragedFitsSameFloatsForAnyThreadCount) {
    Plane p = make_plane([](int x) { return 0.1f * float(x - kW / 2); }, 0.1f,
                         [](int x, int y, const V3& n) { return 0.3f + 0.4f * n.z() + 0.001f * float(x * y); });
    p.depth_regressor = true, p.average_fits = true, p.spatial_sigma = 1.5f;
    const std::vector<V3> one = regressed(p, 1), two = regressed(p, 2), three = regressed(p, 3);
    EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(V3)), 0);
    EXPECT_EQ(std::memcmp(one.data(), three.data(), one.size() * sizeof(V3)), 0);
}

// The image moved one column to the right: each pixel whose window lies inside both images
// gets the same floats, whether it is fitted alone or four at a time.
TEST(ClothRegression, SameFloatsWhereverThePixelLies) {
    Plane p = make_plane([](int x) { return 0.4f * std::sin(float(x)); }, 0.1f,
                         [](int, int y, const V3& n) { return 0.3f + 0.4f * n.x() + 0.01f * float(y); });
    for (int y = 0; y < kH; ++y)  // cloth that is not flat: every weight term in play
        for (int x = 0; x < kW; ++x) p.depth[std::size_t(y) * kW + x] = 2.0f + 0.004f * std::sin(0.7f * x + 0.3f * y);
    Plane moved = p;
    for (int y = 0; y < kH; ++y)
        for (int x = kW - 1; x > 0; --x) {
            const std::size_t to = std::size_t(y) * kW + x, from = to - 1;
            moved.clean[to] = p.clean[from], moved.noisy[to] = p.noisy[from];
            moved.guide[to] = p.guide[from], moved.variance[to] = p.variance[from], moved.noise[to] = p.noise[from];
            moved.nx[to] = p.nx[from], moved.ny[to] = p.ny[from], moved.nz[to] = p.nz[from];
            moved.depth[to] = p.depth[from], moved.cloth[to] = p.cloth[from];
            moved.ax[to] = p.ax[from], moved.ay[to] = p.ay[from], moved.az[to] = p.az[from];
        }
    for (const bool still : {false, true}) {
        p.depth_regressor = moved.depth_regressor = still;
        const std::vector<V3> a = regressed(p), b = regressed(moved);
        constexpr int kRadius = 4;  // cloth_light_fit.cpp's window
        int compared = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = kRadius; x + 1 + kRadius < kW; ++x) {
                const std::size_t i = std::size_t(y) * kW + x;
                EXPECT_EQ(std::memcmp(&a[i], &b[i + 1], sizeof(V3)), 0)
                    << "x " << x << ", y " << y << (still ? ", still" : ", frame");
                ++compared;
            }
        EXPECT_GT(compared, 0);
    }
}

}  // namespace cloth_light_fit_test
}  // namespace foldcast::render
