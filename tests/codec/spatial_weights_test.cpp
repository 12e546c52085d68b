// Weighted spatial prediction (spatial_weights.hpp): the parallelogram's weights are exactly
// r_a + r_b - r_c, fitted weights predict a noisy field better than the parallelogram, the
// weights survive the side information bit for bit, and the second parallelograms of a grid
// are real parallelograms on another edge.
#include <gtest/gtest.h>

#include <random>

#include "bit_stream.hpp"
#include "spatial_weights.hpp"
#include "test_animations.hpp"

namespace foldcast::codec {
namespace spatial_weights_test {

constexpr std::size_t kCols = 30, kRows = 20, kN = kCols * kRows;

TEST(SpatialWeights, SecondParallelogramsOfAGridLieOnAnotherEdge) {
    const auto triangles = test::grid_triangles(kCols, kRows);
    const SpatialTaps taps = spatial_taps(kN, triangles);
    const auto &first = taps.first, &second = taps.second;
    std::size_t with_second = 0;
    for (std::size_t v = 0; v < kN; ++v) {
        const SpatialReference &s = first[v], &s2 = second[v];
        if (s2.c < 0) continue;
        ++with_second;
        EXPECT_GE(s.c, 0) << v;  // a second only where there is a first
        for (std::int32_t u : {s2.a, s2.b, s2.c}) EXPECT_LT(u, std::int32_t(v));
        EXPECT_FALSE((s.a == s2.a && s.b == s2.b) || (s.a == s2.b && s.b == s2.a)) << v;
        // On a flat regular grid a parallelogram's corners satisfy a + b - c = v.
        for (auto [a, b, c] : {std::array{s.a, s.b, s.c}, std::array{s2.a, s2.b, s2.c}}) {
            const auto col = [](std::int32_t u) { return u % std::int32_t(kCols); };
            const auto row = [](std::int32_t u) { return u / std::int32_t(kCols); };
            EXPECT_EQ(col(a) + col(b) - col(c), col(std::int32_t(v))) << v;
            EXPECT_EQ(row(a) + row(b) - row(c), row(std::int32_t(v))) << v;
        }
    }
    // Every vertex away from the first row and the last column has one.
    EXPECT_GE(with_second, (kRows - 2) * (kCols - 2));
}

TEST(SpatialWeights, ParallelogramWeightsAreTheParallelogram) {
    const auto triangles = test::grid_triangles(kCols, kRows);
    const SpatialTaps taps = spatial_taps(kN, triangles);
    const auto &first = taps.first, &second = taps.second;
    std::mt19937 rng(3);
    std::uniform_int_distribution<std::int64_t> value(-(std::int64_t(1) << 31), std::int64_t(1) << 31);
    std::vector<std::int64_t> r(3 * kN);
    for (auto& x : r) x = value(rng);
    for (std::size_t v = 0; v < kN; ++v)
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(weighted_prediction(first[v], second[v], kParallelogramWeights, r.data(), c),
                      spatial_prediction(first[v], r.data(), c));
}

TEST(SpatialWeights, FittedWeightsPredictANoisyFieldBetter) {
    const auto triangles = test::grid_triangles(kCols, kRows);
    const SpatialTaps taps = spatial_taps(kN, triangles);
    const auto &first = taps.first, &second = taps.second;
    // A smooth residual field plus independent noise of the size of the closed loop's.
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0.0, 40.0);
    std::vector<std::int32_t> target(3 * kN), temporal(3 * kN, 0);
    for (std::size_t v = 0; v < kN; ++v)
        for (std::size_t c = 0; c < 3; ++c) {
            const double x = double(v % kCols), y = double(v / kCols);
            target[3 * v + c] = static_cast<std::int32_t>(
                std::lround(300.0 * std::sin(0.3 * x + double(c)) * std::cos(0.2 * y) + noise(rng)));
        }
    const SpatialWeights fitted = fit_spatial_weights(first, second, target.data(), temporal.data());
    EXPECT_NE(fitted, kParallelogramWeights);
    auto squared_error = [&](const SpatialWeights& w) {
        double sum = 0.0;
        for (std::size_t v = 0; v < kN; ++v)
            for (int c = 0; c < 3; ++c) {
                const double e = double(target[3 * v + std::size_t(c)]) -
                                 double(weighted_prediction(first[v], second[v], w, target.data(), c));
                sum += e * e;
            }
        return sum;
    };
    EXPECT_LT(squared_error(fitted), 0.7 * squared_error(kParallelogramWeights));
}

TEST(SpatialWeights, SideInformationRoundTrips) {
    const SpatialWeights own = {127, -128, -1, 0, 64, -64};
    BitWriter out;
    write_spatial_weights(out, SpatialMode::none, own);  // nothing for a frame without spatial prediction
    write_spatial_weights(out, SpatialMode::parallelogram, kParallelogramWeights);
    write_spatial_weights(out, SpatialMode::isometric, own);
    const std::string bytes = out.finish();
    EXPECT_EQ(bytes.size(), (1 + 1 + kSpatialTaps * kWeightBits + 7) / 8);
    BitReader in(bytes);
    EXPECT_EQ(read_spatial_weights(in, SpatialMode::none), kParallelogramWeights);
    EXPECT_EQ(read_spatial_weights(in, SpatialMode::parallelogram), kParallelogramWeights);
    EXPECT_EQ(read_spatial_weights(in, SpatialMode::isometric), own);
    EXPECT_FALSE(in.overrun());
}

}  // namespace spatial_weights_test
}  // namespace foldcast::codec
