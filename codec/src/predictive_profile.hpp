#pragma once
// Profile `default` (docs/codec.md): positions snapped to a uniform grid of step Delta (the
// only loss: at most Delta/2 per coordinate), then coded losslessly on that grid in
// integers: hierarchical temporal prediction (keyframes every 2^L frames, then midpoints
// by cubic/linear interpolation of decoded frames, coarse to fine), spatial prediction of
// the temporal residual across mesh neighbours (parallelogram rule), zstd per packet.
// Integers make encoder and decoder agree bit for bit on every machine.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "foldcast/core/mesh.hpp"

namespace foldcast::codec {

// Which decoded frames predict frame t, and how.
struct TemporalReference {
    enum class Kind { none, copy, linear, cubic } kind = Kind::none;
    std::array<std::size_t, 4> frames{};  // copy: [0]; linear: [0], [1] (a < t < b); cubic: t-3h, t-h, t+h, t+3h
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
};

// Per vertex: earlier vertices whose residuals predict this one's: (a, b, c) means
// r_a + r_b - r_c; c = -1: r_a only; a = -1: no prediction.
struct SpatialReference {
    std::int32_t a = -1, b = -1, c = -1;
};
std::vector<SpatialReference> spatial_references(std::size_t vertices, const std::vector<Triangle>& triangles);

int default_stride_log2(std::size_t frames);

// Grid coordinates must stay below this so every intermediate fits comfortably in int64.
constexpr std::int64_t kMaxGridValue = std::int64_t(1) << 30;

// Adaptive models of the residuals, one per (frame level class, coordinate, magnitude of
// the spatial neighbour's residual); they carry over from packet to packet.
class ResidualContexts;

// Packet payloads in streaming order; `grid` holds T x 3N grid coordinates (frame-major).
std::vector<std::string> predictive_packets(const PredictiveLayout& layout, const std::vector<SpatialReference>& spatial,
                                            std::size_t vertices, const std::vector<std::int32_t>& grid);

}  // namespace foldcast::codec
