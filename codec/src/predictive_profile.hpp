#pragma once
// Profile `default` (docs/codec.md): positions on a fine uniform grid of step d, coded by
// closed-loop prediction in integers: each coordinate is predicted from already decoded
// values (hierarchical temporal prediction: keyframes every 2^L frames, then midpoints by
// cubic/linear interpolation of decoded frames, coarse to fine; plus optionally a spatial
// prediction of the temporal residual across mesh neighbours, parallelogram rule), and the
// prediction error is quantised with step m grid units, so every decoded coordinate is
// within (m + 1) d / 2 of the original.  Each frame's prediction mode is chosen by the
// encoder and sent.  Static-model rANS of one token per vertex (residual_tokens.hpp).
// Integers make encoder and decoder agree bit for bit on every machine.
#include <array>
#include <climits>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "foldcast/core/mesh.hpp"

namespace foldcast::codec {

// Which decoded frames predict frame t, and how.
struct TemporalReference {
    enum class Kind { none, copy, linear, cubic } kind = Kind::none;
    std::array<std::size_t, 4> frames{};  // copy: [0]; linear: [0], [1] (a < t < b); cubic: t-3h, t-h, t+h, t+3h
    // How many of `frames` it reads (every mode's frames are among them).
    std::size_t count() const {
        return kind == Kind::cubic ? 4 : kind == Kind::linear ? 2 : kind == Kind::copy ? 1 : 0;
    }
};

struct PredictiveLayout {
    PredictiveLayout(std::size_t frames, int stride_log2);
    std::size_t frames;
    std::size_t stride;
    // packets[0] = keyframes; packets[g + 1] = refinement frames of group g, coarse to fine.
    std::vector<std::vector<std::size_t>> packets;
    std::vector<TemporalReference> references;  // per frame
    std::vector<int> level_class;               // per frame: 0 keyframe, 1 + log2(h) for midpoints at spacing h
    std::vector<std::size_t> playable_after;    // frames final once packets [0, k) arrived
    std::vector<char> referenced;               // per frame: some frame predicts from it
    std::vector<char> referenced_later;         // per frame: a later packet predicts from it (the keyframes)
};

// Per vertex: earlier vertices whose residuals predict this one's: (a, b, c) means
// r_a + r_b - r_c; c = -1: r_a only; a = -1: no prediction.
struct SpatialReference {
    std::int32_t a = -1, b = -1, c = -1;
};
std::vector<SpatialReference> spatial_references(std::size_t vertices, const std::vector<Triangle>& triangles);
// Per vertex, its spatial references (`first`, as above) and a second parallelogram on
// another edge whose corners all come before it (`second`; (-1, -1, -1) where it has none):
// the six taps of the weighted spatial prediction (spatial_weights.hpp), found in one pass.
struct SpatialTaps {
    std::vector<SpatialReference> first, second;
};
SpatialTaps spatial_taps(std::size_t vertices, const std::vector<Triangle>& triangles);

// Log2 of the keyframe stride the encoder uses for T frames of N vertices.  Each group (the
// frames between two keyframes) is one packet with frequency tables of its own (about
// 1-2 kbit): the stride grows from 16 until a group holds kGroupVertexFrames, so small
// meshes do not pay for tables every 16 frames, while large ones keep a packet per 16
// frames; at most one group for the whole animation.  docs/codec.md has the measurements.
constexpr std::size_t kGroupVertexFrames = std::size_t(1) << 17;
int default_stride_log2(std::size_t frames, std::size_t vertices);

// Closed-loop residual quantiser step m, in fine-grid units (header field `threshold`):
// the grid step is d = Delta / (m + 1) for a per-coordinate bound Delta / 2.  m = 1 with
// d = Delta codes the grid positions losslessly (every residual is exact).
constexpr std::uint32_t kDefaultResidualStep = 32;
constexpr std::uint32_t kMaxResidualStep = 1024;

// Grid coordinates must stay below this so every intermediate fits comfortably in int64.
constexpr std::int64_t kMaxGridValue = std::int64_t(1) << 30;

// Per-frame prediction mode, sent before the frame's residuals as one integer: 2 * temporal
// + spatial, or kIsometricModes + temporal.  temporal: the layout's reference
// (TemporalReference above), the linear one between the frames the layout interpolates
// (midpoints only), a copy of the left or right one (midpoints only), or no temporal
// prediction; spatial: whether the temporal residual is predicted across mesh neighbours as
// well; isometric (profile `cascade`, format 5): that prediction moved onto the circle the
// vertex's edge lengths allow, the residual quantised along the circle's axes
// (isometric_prediction.hpp).
enum class TemporalMode : int { layout = 0, linear = 1, copy_left = 2, copy_right = 3, none = 4 };
enum class SpatialMode : int { none, parallelogram, isometric };
constexpr int kTemporalModes = 5;
constexpr int kIsometricModes = 2 * kTemporalModes;  // the first isometric mode
constexpr int kFrameModes = kIsometricModes + kTemporalModes;
constexpr TemporalMode temporal_mode(int mode) {
    return static_cast<TemporalMode>(mode >= kIsometricModes ? mode - kIsometricModes : mode / 2);
}
constexpr SpatialMode spatial_mode(int mode) {
    return mode >= kIsometricModes ? SpatialMode::isometric
           : mode % 2 == 1         ? SpatialMode::parallelogram
                                   : SpatialMode::none;
}
// `extended`: whether the file may use the isometric modes (extended_modes; never where
// nothing is decoded before the frame).
bool frame_mode_allowed(const TemporalReference& reference, int mode, bool extended);
// The two decoded frames a midpoint lies between (left < t < right); keyframes: the
// previous keyframe twice.  An isometric frame keeps the edge lengths of the left one.
std::pair<std::size_t, std::size_t> bracket(const TemporalReference& reference);

// The step of an isometric frame whose grid-axis step is `step`: the prediction and the
// reconstruction are each rounded to the grid (half a grid step per coordinate, twice,
// where grid-axis quantisation rounds once), so the step is at most m - 1 and the
// Euclidean error stays within sqrt(3) (m + 1) / 2 grid steps, the bound --max-error-m
// sets.  0 where m is too small for it (no isometric modes).
constexpr std::int64_t isometric_step(std::int64_t step, std::int64_t m) { return step < m - 1 ? step : m - 1; }

// The first format version whose `cascade` files may use the isometric modes and weights of
// their own (spatial_weights.hpp): "extended" files, where the residual step m leaves room
// for an isometric step (m >= 2).
constexpr std::uint16_t kExtendedVersion = 5;
constexpr bool extended_modes(bool cascade, std::int64_t m) { return cascade && isometric_step(m, m) >= 1; }

// From this format version on, extended files code each escape with the table of its
// context (residual_tokens.hpp: escape_context); earlier files and the other profiles with
// one escape table.
constexpr std::uint16_t kEscapeContextVersion = 6;

// A frame's spatial weights, sent by extended files (spatial_weights.hpp): six taps in
// 64ths; the parallelogram r_a + r_b - r_c is (64, 64, -64, 0, 0, 0).
constexpr int kSpatialTaps = 6;
constexpr int kWeightBits = 8;   // two's complement: weights in [-2, 2) at kWeightShift
constexpr int kWeightShift = 6;  // weights in 64ths
using SpatialWeights = std::array<std::int32_t, kSpatialTaps>;
constexpr SpatialWeights kParallelogramWeights = {1 << kWeightShift, 1 << kWeightShift, -(1 << kWeightShift), 0, 0, 0};

// How a frame's residuals become coordinates, the same for the encoder's trials and the
// decoder: its spatial prediction and weights (the parallelogram's unless the frame sends its
// own), its residual step and, for an isometric frame, the decoded frame whose edge lengths
// it keeps.
struct FrameCoding {
    SpatialMode spatial = SpatialMode::none;
    SpatialWeights weights = kParallelogramWeights;
    std::int64_t step = 1;
    const std::int32_t* lengths = nullptr;
};

// The largest |q| a frame of step s can carry: more cannot land on the grid.  Along the
// isometric axes a residual can be sqrt(3) times a grid-axis one.
constexpr std::int64_t largest_residual(std::int64_t s, SpatialMode spatial) {
    const std::int64_t span = (kMaxGridValue + 2 * kMaxResidualStep) * (spatial == SpatialMode::isometric ? 2 : 1);
    return span / s + 1 < INT32_MAX ? span / s + 1 : INT32_MAX;
}

// Residual step of a frame of level class L (PredictiveLayout::level_class) for the header's
// step m.  `default`: m everywhere.  `cascade`: the frames others are predicted from are
// quantised finer (m / 2 for keyframes and spacings >= 4, 3m / 4 at spacing 2; the
// unreferenced spacing-1 frames m), which costs bits there but makes every prediction from
// them better and lowers the error of the frames predicted to within the step
// (docs/codec.md).  Never coarser than m, so the error bound holds.
constexpr std::int64_t level_residual_step(std::int64_t m, int level_class, bool cascade) {
    if (!cascade || level_class == 1) return m;
    const std::int64_t step = level_class == 2 ? 3 * m / 4 : m / 2;
    return step < 1 ? 1 : step;
}

constexpr int kModeBits = 4;  // per frame, in the packet's side information

// Temporal prediction of every coordinate of frame t in `mode` (frame_mode_allowed) from
// decoded frames (frames[f]: frame f's 3N grid coordinates; only the references are read);
// encoder and decoder share it, so they agree bit for bit.  `largest` bounds the magnitude
// of every coordinate read: small enough (cubic_fits_int32), the cubic is computed in int32,
// which vectorises twice as wide, with the same result.  Predictions of in-range frames
// stay within int32.
void predict_frame(const TemporalReference& reference, TemporalMode mode, std::size_t t,
                   const std::int32_t* const* frames, std::size_t row, std::int64_t largest, std::int32_t* out);
constexpr bool cubic_fits_int32(std::int64_t largest) { return 20 * largest + 8 <= std::int64_t(INT32_MAX); }

// Spatial prediction of coordinate c's temporal residual at a vertex: r_a + r_b - r_c.
template <typename Residual>
inline std::int64_t spatial_prediction(const SpatialReference& s, const Residual* residual, int c) {
    if (s.a < 0) return 0;
    const std::int64_t ra = residual[3 * static_cast<std::size_t>(s.a) + static_cast<std::size_t>(c)];
    if (s.c < 0) return ra;
    return ra + residual[3 * static_cast<std::size_t>(s.b) + static_cast<std::size_t>(c)] -
           residual[3 * static_cast<std::size_t>(s.c) + static_cast<std::size_t>(c)];
}

// The frequency tables a packet carries a keep-or-replace flag for, in order: the token
// tables of each level class its frames have (ascending), then its escape tables: one, or
// one per context where the packet codes its escapes in context.
std::vector<int> packet_table_ids(const PredictiveLayout& layout, const std::vector<std::size_t>& frames,
                                  bool escapes_in_context);

// Packet payloads in streaming order; `grid` holds T x 3N fine-grid coordinates
// (frame-major), `residual_step` is m.  `forced_mode` >= 0 codes every frame in that mode
// where allowed (tests); otherwise the encoder picks each frame's cheapest mode.  `cascade`:
// profile `cascade` (level_residual_step).
std::vector<std::string> predictive_packets(const PredictiveLayout& layout, const std::vector<Triangle>& triangles,
                                            std::size_t vertices, const std::vector<std::int32_t>& grid,
                                            std::uint32_t residual_step, int forced_mode = -1, bool cascade = false);

}  // namespace foldcast::codec
