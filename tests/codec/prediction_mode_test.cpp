// The default profile's per-frame prediction modes and its closed-loop residual quantiser
// (codec/src/predictive_profile.*): every mode decodes to what the encoder meant, the
// encoder's choice pays off on an abrupt change, and the error bound holds for any m.
#include <gtest/gtest.h>

#include <cmath>

#include "foldcast/codec/codec.hpp"
#include "foldcast/core/error.hpp"
#include "grid_round_trip.hpp"

namespace foldcast::codec {
namespace {

constexpr std::size_t kCols = 12, kRows = 10;

// Grid coordinates (T x 3N, frame-major) of a sheet drifting smoothly; from `jump_frame`
// on, a fold pattern (smooth across the sheet, large against the motion) switches on.
std::vector<std::int32_t> sheet_grid(std::size_t frames, std::size_t jump_frame) {
    const std::size_t n = kCols * kRows;
    std::vector<std::int32_t> g(frames * 3 * n);
    for (std::size_t t = 0; t < frames; ++t)
        for (std::size_t v = 0; v < n; ++v) {
            const double x = double(v % kCols), y = double(v / kCols);
            const double fold = t >= jump_frame ? 4000.0 * std::sin(0.7 * y) : 0.0;
            const double p[3] = {20000.0 + 1000.0 * x + 37.0 * double(t), 20000.0 + 1000.0 * y + 0.5 * double(t * t),
                                 20000.0 + 300.0 * std::sin(0.3 * x + 0.05 * double(t)) + fold};
            for (int c = 0; c < 3; ++c)
                g[(t * n + v) * 3 + static_cast<std::size_t>(c)] = static_cast<std::int32_t>(std::lround(p[c]));
        }
    return g;
}

// Encodes with `mode` (-1: the encoder's choice) and decodes through the profile decoder;
// the grid step is 1 m so decoded positions are grid coordinates.
test::Coded code(const std::vector<std::int32_t>& grid, std::size_t frames, std::uint32_t m, int mode,
                 float bounds_scale = 1.0f) {
    return test::round_trip({grid, kCols, kRows, frames}, Profile::predictive, m, mode,
                            default_stride_log2(frames, kCols * kRows), bounds_scale);
}

std::int64_t max_abs_error(const std::vector<std::int32_t>& a, const std::vector<std::int32_t>& b) {
    std::int64_t worst = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        worst = std::max<std::int64_t>(worst, std::abs(std::int64_t(a[i]) - b[i]));
    return worst;
}

TEST(PredictionModes, EveryModeRoundTripsWithinHalfTheResidualStep) {
    const std::size_t frames = 40;
    const auto grid = sheet_grid(frames, 21);
    for (std::uint32_t m : {1u, 6u, 32u})
        for (int mode = 0; mode < kIsometricModes; ++mode) {
            const test::Coded c = code(grid, frames, m, mode);
            // m = 1 is lossless; otherwise every coordinate is within m / 2 grid units.
            EXPECT_LE(max_abs_error(grid, c.decoded), std::int64_t(m / 2)) << "m " << m << " mode " << mode;
        }
}

TEST(PredictionModes, ModesAreAllowedOnlyWhereTheirReferencesExist) {
    const PredictiveLayout layout(40, 4);
    for (bool isometric : {false, true}) {
        EXPECT_TRUE(frame_mode_allowed(layout.references[0], 0, isometric));
        EXPECT_FALSE(frame_mode_allowed(layout.references[0], 2 * int(TemporalMode::copy_left), isometric));
        EXPECT_TRUE(frame_mode_allowed(layout.references[16], 2 * int(TemporalMode::none) + 1, isometric));  // keyframe
        EXPECT_FALSE(frame_mode_allowed(layout.references[16], 2 * int(TemporalMode::copy_right), isometric));
        EXPECT_FALSE(frame_mode_allowed(layout.references[8], kFrameModes, isometric));
        EXPECT_FALSE(frame_mode_allowed(layout.references[8], -1, isometric));
    }
    for (int mode = 0; mode < kIsometricModes; ++mode)
        EXPECT_TRUE(frame_mode_allowed(layout.references[8], mode, false));
    // The isometric modes: only where the file allows them, with the same temporal references.
    for (int mode = kIsometricModes; mode < kFrameModes; ++mode) {
        EXPECT_FALSE(frame_mode_allowed(layout.references[8], mode, false));
        EXPECT_TRUE(frame_mode_allowed(layout.references[8], mode, true));
        EXPECT_EQ(frame_mode_allowed(layout.references[16], mode, true),
                  frame_mode_allowed(layout.references[16], 2 * (mode - kIsometricModes) + 1, true));
    }
}

TEST(PredictionModes, EncoderChoiceBeatsTheFixedHierarchyAcrossAnAbruptJump) {
    const std::size_t frames = 48;
    const auto grid = sheet_grid(frames, 21);  // inside a 16-frame group: poisons its interpolations
    const test::Coded chosen = code(grid, frames, 8, -1);
    const test::Coded fixed = code(grid, frames, 8, 1);  // the layout's reference + spatial prediction every frame
    EXPECT_LE(max_abs_error(grid, chosen.decoded), 4);
    // Both files carry the same kind of side information (frequency tables: about half of
    // so small a file), so the residuals' saving shows as a smaller share of the total.
    EXPECT_LT(double(chosen.bytes), 0.9 * double(fixed.bytes)) << chosen.bytes << " vs " << fixed.bytes;
    for (int mode = 0; mode < kIsometricModes; ++mode)  // no single mode does better than choosing per frame
        EXPECT_LE(double(chosen.bytes), 1.05 * double(code(grid, frames, 8, mode).bytes)) << "mode " << mode;
}

TEST(PredictionModes, ClosedLoopQuantiserCostsLessThanCodingTheGridLosslessly) {
    // Same error bound: m = 1 on a grid of step Delta vs m = 15 on a grid of step Delta / 16.
    const std::size_t frames = 160, n = kCols * kRows;
    std::vector<std::int32_t> coarse(frames * 3 * n), fine(frames * 3 * n);
    const auto exact = sheet_grid(frames, frames);  // smooth, no jump; units of Delta / 100
    for (std::size_t i = 0; i < exact.size(); ++i) {
        coarse[i] = static_cast<std::int32_t>(std::lround(exact[i] / 100.0));
        fine[i] = static_cast<std::int32_t>(std::lround(exact[i] / 100.0 * 16.0));
    }
    const std::size_t closed_loop = code(fine, frames, 15, -1).bytes, lossless = code(coarse, frames, 1, -1).bytes;
    EXPECT_LT(double(closed_loop), 0.7 * double(lossless)) << closed_loop << " vs " << lossless;
}

TEST(PredictionModes, CoordinatesBeyondTheHeaderBoundsAreCorruptData) {
    const std::vector<std::int32_t> grid = sheet_grid(17, 17);
    EXPECT_NO_THROW(code(grid, 17, 32, -1));
    try {
        code(grid, 17, 32, -1, 0.5f);
        FAIL() << "a frame beyond the header's bounds decoded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("leaves the quantisation grid"), std::string::npos) << e.what();
    }
}

TEST(PredictionModes, HeaderResidualStepOutsideItsRangeIsRejected) {
    Header h;
    h.vertices = 3;
    h.frames = 2;
    h.step = 1e-3;
    h.topology.triangles = {{0, 1, 2}};
    for (double m : {0.0, 2.5, double(kMaxResidualStep) + 1.0}) {
        h.threshold = m;
        EXPECT_THROW((void)make_predictive_decoder(h, "test"), InputError) << m;
    }
    h.threshold = 32.0;
    EXPECT_NO_THROW((void)make_predictive_decoder(h, "test"));
}

}  // namespace
}  // namespace foldcast::codec
