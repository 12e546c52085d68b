#pragma once
// Profile `paper`: the reference method (docs/codec.md).  Per-vertex trajectories, velocity
// pre-filter with p(0) sent first, cubic B-spline wavelets on the interval, |c| < eps
// dropped, uniform quantisation, canonical Huffman, packets in depth-first time order.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "foldcast/core/mesh.hpp"
#include "paper_layout.hpp"

namespace foldcast::codec {

using IntMatrix = Eigen::Matrix<std::int32_t, Eigen::Dynamic, Eigen::Dynamic>;

class PaperEncoder {
public:
    explicit PaperEncoder(const Animation& anim);

    // Smallest step that keeps every quantised value codable.
    double min_step() const;
    // eps such that `fraction` of the wavelet coefficients have |c| >= eps.
    double threshold_for_keep(double fraction) const;
    // Max vertex error (metres) of the decoded animation for these settings.
    double max_error_m(double step, double threshold) const;
    // Data packet payloads (without the sequence number), in streaming order.
    std::vector<std::string> packets(double step, double threshold) const;

private:
    IntMatrix quantise(double step, double threshold) const;
    const Animation& anim_;
    PaperLayout layout_;
    Eigen::MatrixXd coefficients_;  // weighted, rows = wavelet layout, cols = 3N trajectories
};

// Decoder side: dequantised coefficients + p(0) -> T frames.
void paper_reconstruct(const PaperLayout& layout, const std::vector<Vec3f>& first_frame, const IntMatrix& quantised,
                       double step, std::vector<std::vector<Vec3f>>& frames);

}  // namespace foldcast::codec
