#pragma once
// A T x 3N grid-coordinate sequence on a cols x rows sheet coded by predictive_packets and
// decoded by the profile decoder, with the grid step 1 m so that the decoded positions are
// grid coordinates: the predictive profiles' white-box round trip.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "container.hpp"
#include "predictive_profile.hpp"
#include "profile_decoder.hpp"
#include "test_animations.hpp"

namespace foldcast::test {

struct Coded {
    std::vector<std::string> packets;
    std::vector<std::int32_t> decoded;  // T x 3N grid coordinates the decoder reconstructs
    std::size_t bytes = 0;
};

struct GridSequence {
    const std::vector<std::int32_t>& grid;
    std::size_t cols, rows, frames;
};

// `mode` as predictive_packets' forced_mode; `bounds_scale` scales the header's bounds (the
// decoder bounds the grid's range by them).
inline Coded round_trip(const GridSequence& s, codec::Profile profile, std::uint32_t m, int mode, int stride_log2,
                        float bounds_scale = 1.0f) {
    const std::size_t n = s.cols * s.rows;
    codec::Header h;
    h.profile = profile;
    h.vertices = static_cast<std::uint32_t>(n);
    h.frames = static_cast<std::uint32_t>(s.frames);
    h.topology.triangles = grid_triangles(s.cols, s.rows);
    h.step = 1.0;
    // Bounds as the encoder writes them.
    for (std::size_t k = 0; k < s.grid.size(); ++k) {
        const auto c = static_cast<Eigen::Index>(k % 3);
        h.bounds.max[c] = std::max(h.bounds.max[c], static_cast<float>(s.grid[k]));
    }
    h.bounds.max *= bounds_scale;
    h.threshold = m;
    h.profile_param = static_cast<std::uint32_t>(stride_log2);
    const codec::PredictiveLayout layout(s.frames, stride_log2);
    Coded out;
    out.packets =
        codec::predictive_packets(layout, h.topology.triangles, n, s.grid, m, mode, profile == codec::Profile::cascade);
    auto decoder = codec::make_predictive_decoder(h, "test");
    for (std::size_t i = 0; i < out.packets.size(); ++i) {
        decoder->accept(i, out.packets[i]);
        out.bytes += out.packets[i].size();
    }
    std::vector<std::vector<Vec3f>> positions;
    decoder->reconstruct(positions);
    for (const auto& f : positions)
        for (const auto& p : f)
            for (int c = 0; c < 3; ++c) out.decoded.push_back(static_cast<std::int32_t>(std::lround(p[c])));
    return out;
}

}  // namespace foldcast::test
