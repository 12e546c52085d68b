// Isometric prediction (isometric_prediction.hpp): the frame lies on the circle the edge
// lengths allow, its axes are orthonormal, quantisation along them keeps the Euclidean bound,
// degenerate corners fall back, corrupt values clamp, and on a sheet that bends without
// stretching the isometric modes cost less than the parallelogram's.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "grid_round_trip.hpp"
#include "isometric_prediction.hpp"

namespace foldcast::codec {
namespace isometric_test {

double distance2(const double* a, const std::int64_t* b) {
    double s = 0.0;
    for (int c = 0; c < 3; ++c) s += (a[c] - double(b[c])) * (a[c] - double(b[c]));
    return s;
}

IsometricInputs hinge(double angle_radians) {
    // a at the origin, b along y; v 1000 units from both (in the frame whose lengths are kept),
    // folded about a-b.
    IsometricInputs in{};
    const std::int64_t a[3] = {50000, 50000, 50000}, b[3] = {50000, 51000, 50000};
    for (int c = 0; c < 3; ++c) {
        in.xa[c] = in.la[c] = a[c];
        in.xb[c] = in.lb[c] = b[c];
    }
    const std::int64_t pv[3] = {51000, 50500, 50000};  // flat in the prediction
    for (int c = 0; c < 3; ++c) in.lv[c] = in.p0[c] = pv[c];
    in.p0[2] += static_cast<std::int64_t>(std::lround(1000.0 * std::sin(angle_radians)));  // the prediction rises
    return in;
}

TEST(IsometricPrediction, FrameLiesOnTheCircleWithOrthonormalAxes) {
    IsometricFrame f;
    ASSERT_TRUE(isometric_frame(hinge(0.4), f));
    const IsometricInputs in = hinge(0.4);
    // The kept lengths: |lv - la|^2 = 1000^2 + 500^2, |lv - lb|^2 the same.
    EXPECT_NEAR(distance2(f.origin, in.xa), 1250000.0, 1e-3);
    EXPECT_NEAR(distance2(f.origin, in.xb), 1250000.0, 1e-3);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double d = 0.0;
            for (int c = 0; c < 3; ++c) d += f.axis[i][c] * f.axis[j][c];
            EXPECT_NEAR(d, i == j ? 1.0 : 0.0, 1e-12) << i << " " << j;
        }
    // The nearest point of the circle to a prediction raised above the flat sheet.
    EXPECT_NEAR(f.origin[1], 50500.0, 1e-9);
    EXPECT_GT(f.origin[2], 50000.0);
}

TEST(IsometricPrediction, ABendWithoutStretchIsOneValueAlongTheTangent) {
    IsometricFrame f;
    ASSERT_TRUE(isometric_frame(hinge(0.2), f));
    // The true vertex folded a little further about a-b, its lengths kept (further, the chord
    // to it leaves the tangent: the frame is linear).
    const double angle = 0.25;
    const std::int32_t target[3] = {static_cast<std::int32_t>(std::lround(50000 + 1000 * std::cos(angle))), 50500,
                                    static_cast<std::int32_t>(std::lround(50000 + 1000 * std::sin(angle)))};
    std::int64_t q[3];
    isometric_quantise(f, target, 8, q);
    EXPECT_NE(q[0], 0);  // the hinge angle
    EXPECT_EQ(q[1], 0);  // towards the circle's centre: no stretch
    EXPECT_EQ(q[2], 0);  // along a-b: none
}

TEST(IsometricPrediction, QuantisationKeepsTheEuclideanBound) {
    std::mt19937 rng(7);
    std::uniform_int_distribution<std::int64_t> coordinate(0, 1 << 20), offset(-3000, 3000);
    int frames = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        IsometricInputs in;
        for (int c = 0; c < 3; ++c) {
            in.xa[c] = coordinate(rng);
            in.xb[c] = in.xa[c] + offset(rng);
            in.la[c] = coordinate(rng);
            in.lb[c] = in.la[c] + offset(rng);
            in.lv[c] = in.la[c] + offset(rng);
            in.p0[c] = in.xa[c] + offset(rng);
        }
        IsometricFrame f;
        if (!isometric_frame(in, f)) continue;
        ++frames;
        std::int32_t target[3];
        for (int c = 0; c < 3; ++c) target[c] = static_cast<std::int32_t>(in.p0[c] + offset(rng));
        for (std::int64_t s : {1, 7, 31}) {
            std::int64_t q[3], back[3];
            isometric_quantise(f, target, s, q);
            isometric_reconstruct(f, q, s, back);
            double e2 = 0.0;
            for (int c = 0; c < 3; ++c) e2 += double(back[c] - target[c]) * double(back[c] - target[c]);
            ASSERT_LE(std::sqrt(e2), std::sqrt(3.0) * double(s + 1) / 2.0 + 1e-9) << "trial " << trial << " s " << s;
        }
    }
    EXPECT_GT(frames, 19000);
}

TEST(IsometricPrediction, DegenerateCornersFallBackAndCorruptValuesClamp) {
    IsometricInputs in = hinge(0.3);
    IsometricFrame f;
    for (int c = 0; c < 3; ++c) in.xb[c] = in.xa[c];  // a and b on one grid point
    EXPECT_FALSE(isometric_frame(in, f));
    in = hinge(0.0);
    for (int c = 0; c < 3; ++c) in.p0[c] = (in.xa[c] + in.xb[c]) / 2;  // on the axis a-b
    EXPECT_FALSE(isometric_frame(in, f));
    ASSERT_TRUE(isometric_frame(hinge(0.3), f));
    const std::int64_t huge[3] = {std::int64_t(1) << 50, -(std::int64_t(1) << 50), 3};
    std::int64_t out[3];
    isometric_reconstruct(f, huge, 1024, out);
    for (std::int64_t x : out) EXPECT_LE(std::abs(double(x)), kIsometricClamp);
}

// A sheet curling and uncurling without stretching (rolled round cylinders of changing
// radius) and turning: grid coordinates, T x 3N.
constexpr std::size_t kCols = 16, kRows = 14;
std::vector<std::int32_t> curling_sheet(std::size_t frames) {
    std::vector<std::int32_t> g;
    for (std::size_t t = 0; t < frames; ++t) {
        // per grid unit, changing erratically from frame to frame, as cloth in a gust does
        const double curvature = 1.0 / 30000.0 + 1.0 / 5000.0 * std::fmod(0.618034 * double(t), 1.0);
        const double turn = 0.03 * double(t), ct = std::cos(turn), st = std::sin(turn);
        for (std::size_t v = 0; v < kCols * kRows; ++v) {
            // Rolled across the grid's diagonal, so no parallelogram of the grid is flat.
            const double i = 700.0 * double(v % kCols), j = 700.0 * double(v / kCols);
            const double arc = 0.8 * i + 0.6 * j, along = -0.6 * i + 0.8 * j;
            const double bent = std::sin(arc * curvature) / curvature,
                         z = (1.0 - std::cos(arc * curvature)) / curvature;
            const double x = 0.8 * bent - 0.6 * along, y = 0.6 * bent + 0.8 * along;
            for (double p : {60000.0 + ct * x - st * y, 60000.0 + st * x + ct * y, 60000.0 + z})
                g.push_back(static_cast<std::int32_t>(std::lround(p)));
        }
    }
    return g;
}

TEST(IsometricPrediction, BendingClothCostsLessThanWithTheParallelogram) {
    const std::size_t frames = 33;
    const std::vector<std::int32_t> grid = curling_sheet(frames);
    const test::GridSequence sheet{grid, kCols, kRows, frames};
    // Each forced mode still chooses per frame between the parallelogram's weights and fitted ones.
    const int parallelogram = 2 * int(TemporalMode::layout) + 1,
              isometric = kIsometricModes + int(TemporalMode::layout);
    const test::Coded plain = test::round_trip(sheet, Profile::cascade, 32, parallelogram, 4);
    const test::Coded bent = test::round_trip(sheet, Profile::cascade, 32, isometric, 4);
    const test::Coded chosen = test::round_trip(sheet, Profile::cascade, 32, -1, 4);
    EXPECT_LT(bent.bytes, plain.bytes);
    EXPECT_LT(double(chosen.bytes), 0.9 * double(plain.bytes)) << chosen.bytes << " vs " << plain.bytes;
    EXPECT_LE(chosen.bytes, bent.bytes);
}

}  // namespace isometric_test
}  // namespace foldcast::codec
