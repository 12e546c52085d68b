// Profile `motion` (codec/src/rigid_prediction.hpp, level_residual_step): the rigid transport
// follows a folded patch through a rotation that the parallelogram rule misses, every mode
// decodes to what the encoder meant within each frame's half step, the error bound holds,
// and files of the other profiles cannot carry its modes.
#include <gtest/gtest.h>

#include <cmath>

#include "container.hpp"
#include "foldcast/codec/codec.hpp"
#include "foldcast/core/error.hpp"
#include "predictive_profile.hpp"
#include "profile_decoder.hpp"
#include "rigid_prediction.hpp"
#include "test_animations.hpp"

namespace foldcast::codec {
namespace motion_test {

constexpr std::size_t kCols = 14, kRows = 12;

std::vector<Triangle> grid_triangles() {
    std::vector<Triangle> tris;
    for (std::size_t r = 0; r + 1 < kRows; ++r)
        for (std::size_t c = 0; c + 1 < kCols; ++c) {
            const auto v = static_cast<std::uint32_t>(r * kCols + c);
            tris.push_back({v, v + 1, v + static_cast<std::uint32_t>(kCols)});
            tris.push_back({v + 1, v + static_cast<std::uint32_t>(kCols) + 1, v + static_cast<std::uint32_t>(kCols)});
        }
    return tris;
}

// A folded sheet (z a function of x and y) turning about the y axis by `radians` around its
// centre and moving along x: grid coordinates, 3N per frame.
std::vector<std::int32_t> turning_fold(double radians, double shift) {
    std::vector<std::int32_t> g;
    for (std::size_t v = 0; v < kCols * kRows; ++v) {
        const double x = 1000.0 * double(v % kCols) - 6500.0, y = 1000.0 * double(v / kCols) - 5500.0;
        const double z = 2500.0 * std::sin(0.0015 * y) + 800.0 * std::cos(0.001 * x);
        const double c = std::cos(radians), s = std::sin(radians);
        for (double p : {40000.0 + shift + c * x + s * z, 40000.0 + y, 40000.0 - s * x + c * z})
            g.push_back(static_cast<std::int32_t>(std::lround(p)));
    }
    return g;
}

TEST(RigidTransport, FollowsATurningFoldThatTheParallelogramMisses) {
    const auto tris = grid_triangles();
    const auto refs = spatial_references(kCols * kRows, tris);
    const auto before = turning_fold(0.0, 0.0), after = turning_fold(0.6, 3000.0);
    std::int64_t worst_rigid = 0, worst_parallelogram = 0;
    std::size_t transported = 0;
    // Temporal residuals of `after` predicted by copying `before`.
    std::vector<std::int64_t> residual(after.size());
    for (std::size_t k = 0; k < after.size(); ++k) residual[k] = std::int64_t(after[k]) - before[k];
    for (std::size_t v = 0; v < kCols * kRows; ++v) {
        std::int64_t p[3];
        const bool ok = rigid_prediction(refs[v], v, before.data(), after.data(), p);
        for (int c = 0; c < 3; ++c) {
            const std::size_t k = 3 * v + static_cast<std::size_t>(c);
            if (refs[v].c < 0) continue;
            const std::int64_t parallelogram = before[k] + spatial_prediction(refs[v], residual.data(), c);
            worst_parallelogram = std::max(worst_parallelogram, std::abs(parallelogram - after[k]));
            if (ok) worst_rigid = std::max(worst_rigid, std::abs(p[c] - after[k]));
        }
        transported += ok;
    }
    EXPECT_GT(transported, kCols * kRows * 3 / 4);
    // Rounding of the grid coordinates only (a few units) against hundreds.
    EXPECT_LE(worst_rigid, 8);
    EXPECT_GT(worst_parallelogram, 100);
}

TEST(RigidTransport, DegenerateTrianglesFallBack) {
    const SpatialReference s{0, 1, 2};
    const std::int32_t same[12] = {5, 5, 5, 5, 5, 5, 5, 5, 5, 9, 9, 9};  // a, b, c at one point
    std::int64_t out[3] = {-1, -1, -1};
    EXPECT_FALSE(rigid_prediction(s, 3, same, same, out));
    EXPECT_EQ(out[0], -1);
    EXPECT_FALSE(rigid_prediction(SpatialReference{0, -1, -1}, 3, same, same, out));
}

// Through the profile decoder with the grid step 1 m, so positions are grid coordinates.
// `motion`: the encoder's profile; `decode_as_motion` the header's.
std::vector<std::int32_t> code(const std::vector<std::int32_t>& grid, std::size_t frames, std::uint32_t m, int mode,
                               bool motion, bool decode_as_motion) {
    const std::size_t n = kCols * kRows;
    Header h;
    h.profile = decode_as_motion ? Profile::motion : Profile::predictive;
    h.vertices = static_cast<std::uint32_t>(n);
    h.frames = static_cast<std::uint32_t>(frames);
    h.topology.triangles = grid_triangles();
    h.step = 1.0;
    for (std::size_t k = 0; k < grid.size(); ++k) {
        const auto c = static_cast<Eigen::Index>(k % 3);
        h.bounds.max[c] = std::max(h.bounds.max[c], static_cast<float>(grid[k]));
    }
    h.threshold = m;
    h.profile_param = 3;
    const PredictiveLayout layout(frames, 3);
    const auto packets = predictive_packets(layout, spatial_references(n, h.topology.triangles), n, grid, m, mode, motion);
    auto decoder = make_predictive_decoder(h, "test");
    for (std::size_t i = 0; i < packets.size(); ++i) decoder->accept(i, packets[i]);
    std::vector<std::vector<Vec3f>> positions;
    decoder->reconstruct(positions);
    std::vector<std::int32_t> out;
    for (const auto& f : positions)
        for (const auto& p : f)
            for (int c = 0; c < 3; ++c) out.push_back(static_cast<std::int32_t>(std::lround(p[c])));
    return out;
}

std::vector<std::int32_t> turning_sequence(std::size_t frames) {
    std::vector<std::int32_t> g;
    for (std::size_t t = 0; t < frames; ++t) {
        const auto f = turning_fold(0.05 * double(t) + 0.002 * double(t * t), 400.0 * double(t));
        g.insert(g.end(), f.begin(), f.end());
    }
    return g;
}

TEST(MotionProfile, EveryModeRoundTripsWithinEachFramesHalfStep) {
    const std::size_t frames = 20;
    const auto grid = turning_sequence(frames);
    const PredictiveLayout layout(frames, 3);
    for (std::uint32_t m : {1u, 6u, 32u})
        for (int mode = 0; mode < kMotionFrameModes; ++mode) {
            const auto decoded = code(grid, frames, m, mode, true, true);
            ASSERT_EQ(decoded.size(), grid.size());
            for (std::size_t k = 0; k < grid.size(); ++k) {
                const int level = layout.level_class[k / (3 * kCols * kRows)];
                const std::int64_t half = level_residual_step(m, level, true) / 2;
                ASSERT_LE(std::abs(std::int64_t(decoded[k]) - grid[k]), half)
                    << "m " << m << " mode " << mode << " coordinate " << k;
            }
        }
}

TEST(MotionProfile, ReferenceFramesAreQuantisedFinerNeverCoarser) {
    for (std::int64_t m : {1, 2, 3, 32, 1024})
        for (int level = 0; level < 8; ++level) {
            EXPECT_EQ(level_residual_step(m, level, false), m);
            EXPECT_GE(level_residual_step(m, level, true), 1);
            EXPECT_LE(level_residual_step(m, level, true), m);
        }
    EXPECT_EQ(level_residual_step(32, 1, true), 32);
    EXPECT_EQ(level_residual_step(32, 2, true), 24);
    EXPECT_EQ(level_residual_step(32, 0, true), 16);
    EXPECT_EQ(level_residual_step(32, 5, true), 16);
}

TEST(MotionProfile, RigidModesBelongToTheMotionProfileOnly) {
    const PredictiveLayout layout(40, 4);
    for (int rigid = kFrameModes; rigid < kMotionFrameModes; ++rigid) {
        EXPECT_FALSE(frame_mode_allowed(layout.references[8], rigid, false)) << rigid;
        EXPECT_TRUE(frame_mode_allowed(layout.references[8], rigid, true)) << rigid;
        EXPECT_FALSE(frame_mode_allowed(layout.references[0], rigid, true)) << rigid;  // nothing to transport
    }
    EXPECT_TRUE(frame_mode_allowed(layout.references[16], kFrameModes, true));       // keyframe: its copy
    EXPECT_FALSE(frame_mode_allowed(layout.references[16], kFrameModes + 2, true));  // no bracket there
    EXPECT_FALSE(frame_mode_allowed(layout.references[8], kMotionFrameModes, true));

    // A default-profile header cannot carry a rigid mode: the decoder names it corrupt.
    const std::size_t frames = 20;
    const auto grid = turning_sequence(frames);
    EXPECT_THROW((void)code(grid, frames, 32, kFrameModes + 1, true, false), InputError);
}

TEST(MotionProfile, MeetsItsBoundAndBeatsTheDefaultErrorAtTheSameBound) {
    for (const Animation& a : {test::basic_cloth(), test::wave_grid(40, 40, 64)}) {
        EncodeOptions o;
        o.max_error_m = 2e-4 * bounds(a).diagonal();
        o.profile = Profile::motion;
        const std::string bytes = encode(a, o);
        const Animation back = decode(bytes);
        const Metrics motion = measure(a, back, bytes.size());
        EXPECT_LE(motion.max_error_m, *o.max_error_m * (1 + 1e-6));
        StreamingDecoder d;
        d.feed(bytes);
        EXPECT_EQ(d.profile(), Profile::motion);
        ASSERT_TRUE(d.max_error_m());
        EXPECT_LE(motion.max_error_m, *d.max_error_m() * (1 + 1e-6));
        o.profile = Profile::predictive;
        const std::string plain = encode(a, o);
        const Metrics standard = measure(a, decode(plain), plain.size());
        EXPECT_LT(motion.kg_error, standard.kg_error);
        EXPECT_EQ(encode(a, EncodeOptions{Profile::motion, o.max_error_m, {}, {}}),
                  encode(a, EncodeOptions{Profile::motion, o.max_error_m, {}, {}}));
    }
    EXPECT_EQ(parse_profile("motion"), Profile::motion);
    EXPECT_EQ(profile_name(Profile::motion), "motion");
}

}  // namespace motion_test
}  // namespace foldcast::codec
