// Profile `cascade` (level_residual_step): every mode decodes to what the encoder meant
// within each frame's own half step (isometric ones within its Euclidean bound), no frame is
// quantised coarser than the header's step, the error bound holds, and the finer references
// lower the error at the same bound.
#include <gtest/gtest.h>

#include <cmath>

#include "foldcast/codec/codec.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/core/mesh_io.hpp"
#include "grid_round_trip.hpp"
#include "residual_tokens.hpp"
#include "test_paths.hpp"

namespace foldcast::codec {
namespace cascade_test {

constexpr std::size_t kCols = 14, kRows = 12;

// A folded sheet turning about the y axis and moving along x (grid coordinates, T x 3N).
std::vector<std::int32_t> turning_sequence(std::size_t frames) {
    std::vector<std::int32_t> g;
    for (std::size_t t = 0; t < frames; ++t) {
        const double radians = 0.05 * double(t) + 0.002 * double(t * t), shift = 400.0 * double(t);
        const double c = std::cos(radians), s = std::sin(radians);
        for (std::size_t v = 0; v < kCols * kRows; ++v) {
            const double x = 1000.0 * double(v % kCols) - 6500.0, y = 1000.0 * double(v / kCols) - 5500.0;
            const double z = 2500.0 * std::sin(0.0015 * y) + 800.0 * std::cos(0.001 * x);
            for (double p : {40000.0 + shift + c * x + s * z, 40000.0 + y, 40000.0 - s * x + c * z})
                g.push_back(static_cast<std::int32_t>(std::lround(p)));
        }
    }
    return g;
}

// Through the profile decoder (grid_round_trip.hpp), stride 8 frames.
std::vector<std::int32_t> code(const std::vector<std::int32_t>& grid, std::size_t frames, std::uint32_t m, int mode) {
    return test::round_trip({grid, kCols, kRows, frames}, Profile::cascade, m, mode, 3).decoded;
}

TEST(CascadeProfile, EveryModeRoundTripsWithinEachFramesHalfStep) {
    const std::size_t frames = 20, n = kCols * kRows;
    const auto grid = turning_sequence(frames);
    const PredictiveLayout layout(frames, 3);
    for (std::uint32_t m : {1u, 6u, 32u})
        for (int mode = -1; mode < kIsometricModes; ++mode) {
            const auto decoded = code(grid, frames, m, mode);
            ASSERT_EQ(decoded.size(), grid.size());
            std::int64_t worst_fine = 0;
            for (std::size_t k = 0; k < grid.size(); ++k) {
                const int level = layout.level_class[k / (3 * n)];
                const std::int64_t error = std::abs(std::int64_t(decoded[k]) - grid[k]);
                if (mode < 0) continue;  // the encoder's choice may be isometric: the next test's bound
                ASSERT_LE(error, level_residual_step(m, level, true) / 2)
                    << "m " << m << " mode " << mode << " coordinate " << k;
                if (level != 1) worst_fine = std::max(worst_fine, error);
            }
            // The reference frames really are quantised finer than m / 2.
            if (m == 32 && mode >= 0) {
                EXPECT_LE(worst_fine, 12) << "mode " << mode;
            }
        }
}

// Isometric frames (and the encoder's choice, which may pick them) are bounded per vertex
// in Euclidean distance, as --max-error-m is: sqrt(3) (s + 1) / 2 grid units for the frame's
// isometric step s, never more than sqrt(3) (m + 1) / 2.
TEST(CascadeProfile, IsometricModesKeepTheEuclideanBound) {
    const std::size_t frames = 20, n = kCols * kRows;
    const auto grid = turning_sequence(frames);
    const PredictiveLayout layout(frames, 3);
    for (std::uint32_t m : {2u, 6u, 32u})
        for (int mode = kIsometricModes - 1; mode < kFrameModes; ++mode) {
            const int forced = mode < kIsometricModes ? -1 : mode;
            const auto decoded = code(grid, frames, m, forced);
            ASSERT_EQ(decoded.size(), grid.size());
            for (std::size_t v = 0; v < frames * n; ++v) {
                const int level = layout.level_class[v / n];
                double squared = 0.0;
                for (std::size_t c = 0; c < 3; ++c) {
                    const double e = double(decoded[3 * v + c]) - double(grid[3 * v + c]);
                    squared += e * e;
                }
                const std::int64_t s = isometric_step(level_residual_step(m, level, true), m);
                ASSERT_LE(std::sqrt(squared), std::sqrt(3.0) * double(s + 1) / 2.0 + 1e-9)
                    << "m " << m << " mode " << forced << " vertex-frame " << v;
                ASSERT_LE(s + 1, std::int64_t(m) + 1);
            }
        }
}

TEST(CascadeProfile, ReferenceFramesAreQuantisedFinerNeverCoarser) {
    for (std::int64_t m : {1, 2, 3, 32, 1024})
        for (int level = 0; level < 8; ++level) {
            EXPECT_EQ(level_residual_step(m, level, false), m);
            EXPECT_GE(level_residual_step(m, level, true), 1);
            EXPECT_LE(level_residual_step(m, level, true), m);
            EXPECT_GE(level_residual_step(m, level, true), level_residual_step(m, 0, true));
        }
    EXPECT_EQ(level_residual_step(32, 1, true), 32);
    EXPECT_EQ(level_residual_step(32, 2, true), 24);
    EXPECT_EQ(level_residual_step(32, 0, true), 16);
    EXPECT_EQ(level_residual_step(32, 5, true), 16);
    EXPECT_EQ(level_residual_step(1, 0, true), 1);
}

TEST(CascadeProfile, MeetsItsBoundAndHasLessErrorThanDefaultAtTheSameBound) {
    for (const Animation& a : {test::basic_cloth(), test::wave_grid(40, 40, 64)}) {
        EncodeOptions o;
        o.max_error_m = 2e-4 * bounds(a).diagonal();
        o.profile = Profile::cascade;
        const std::string bytes = encode(a, o);
        const Metrics cascade = measure(a, decode(bytes), bytes.size());
        EXPECT_LE(cascade.max_error_m, *o.max_error_m * (1 + 1e-6));
        StreamingDecoder d;
        d.feed(bytes);
        EXPECT_EQ(d.profile(), Profile::cascade);
        ASSERT_TRUE(d.max_error_m());
        EXPECT_LE(cascade.max_error_m, *d.max_error_m() * (1 + 1e-6));
        EXPECT_EQ(encode(a, o), bytes);  // deterministic
        o.profile = Profile::predictive;
        const std::string plain = encode(a, o);
        const Metrics standard = measure(a, decode(plain), plain.size());
        EXPECT_LT(cascade.kg_error, 0.9 * standard.kg_error);
    }
    EXPECT_EQ(parse_profile("cascade"), Profile::cascade);
    EXPECT_EQ(profile_name(Profile::cascade), "cascade");
    EXPECT_THROW((void)parse_profile("motion"), InputError);
}

// Cascade files of earlier formats decode to the same frames: format 4 (finer references
// only) and format 5 (weights and isometric modes, one escape table), each written by that
// build with its decode then (tests/data/fca).
TEST(CascadeProfile, Format4And5FilesStillDecodeBitForBit) {
    for (const int version : {4, 5}) {
        const std::string name = "fca/v" + std::to_string(version) + "_cascade_drape16";
        const std::string file = read_fca(test::test_data(name + ".fca"));
        ASSERT_EQ(file[8 + 5],
                  version);  // the header's version (low byte), after the magic and the packet length and type
        StreamingDecoder decoder(name, file.size());
        decoder.feed(file);
        ASSERT_TRUE(decoder.status().complete) << name;
        EXPECT_EQ(decoder.profile(), Profile::cascade);
        EXPECT_EQ(decoder.animation().frames, read_pc2(test::test_data(name + ".pc2"))) << name;
    }
}

// An escape's context is the larger bit length of the same coordinate's |q| at the vertex's
// two context neighbours; a missing neighbour reads the zeros after the last vertex.
TEST(CascadeProfile, EscapeContextIsTheNeighboursLargerBitLength) {
    // Three vertices, then the three zeros of a missing neighbour (index 3).
    const std::vector<std::int32_t> q = {5, -1, 0, -9, 2, 0, 1000, 0, -3, 0, 0, 0};
    const ContextNeighbours both{0, 1}, far_only{2, 3};
    EXPECT_EQ(escape_context(q.data(), both, 0), 4);  // |5| | |-9|: 4 bits
    EXPECT_EQ(escape_context(q.data(), both, 1), 2);  // 1 and 2
    EXPECT_EQ(escape_context(q.data(), both, 2), 0);
    EXPECT_EQ(escape_context(q.data(), far_only, 0), kEscapeContexts - 1);  // 1000: 10 bits, capped
    EXPECT_EQ(escape_context(q.data(), far_only, 2), 2);
    const std::vector<std::int64_t> wide(q.begin(), q.end());  // the encoder's residuals
    EXPECT_EQ(escape_context(wide.data(), both, 0), 4);
}

}  // namespace cascade_test
}  // namespace foldcast::codec
