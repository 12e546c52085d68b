#pragma once
// The layout shared by the paper profile's encoder and decoder, derived from N and T alone:
// the wavelet level, the depth-first coefficient tree order and how it is cut into packets.
//
// Velocities v(k) = p(k) - p(k-1), k = 1..T-1, form a signal of T-1 samples per vertex
// coordinate.  The wavelet needs 2^J + 3 samples: J is the smallest level >= 3 that holds
// T-1, and the tail is padded with zero velocity (the cloth holds still), which adds no
// energy and nothing to code.
#include <cstdint>
#include <memory>
#include <vector>

#include "bspline_wavelet.hpp"

namespace foldcast::codec {

// The finest wavelet level the paper profile writes or reads: T - 1 <= 2^16 + 3 velocity
// samples (T <= 65,540 frames, 36 minutes at 30 fps).  Building the wavelet costs O(2^J)
// small SVDs (about 2 s at this level) before any coefficient is read, so the decoder
// refuses more: a hostile header cannot make it work for minutes.
inline constexpr int kMaxPaperLevel = 16;
inline constexpr std::size_t kMaxPaperFrames = (std::size_t(1) << kMaxPaperLevel) + 4;

struct PaperLayout {
    PaperLayout(std::size_t vertices, std::size_t frames);

    std::size_t vertices, frames, trajectories;  // trajectories = 3 N
    int level;                                   // J
    std::shared_ptr<const CubicBSplineWavelet> wavelet;
    // Wavelet tree nodes in depth-first, left-to-right order: coefficient rows.
    std::vector<std::size_t> node_rows;
    // Data packet k >= 1 holds nodes [packet_first[k-1], packet_first[k-1] + packet_count[k-1]).
    std::vector<std::size_t> packet_first, packet_count;
    // Frames final once the first k nodes (in order) have arrived: playable_after[k].
    std::vector<std::size_t> playable_after;

    std::size_t data_packets() const { return 1 + packet_first.size(); }  // base + node packets
    static constexpr std::size_t kCoefficientsPerPacket = 4096;
};

}  // namespace foldcast::codec
