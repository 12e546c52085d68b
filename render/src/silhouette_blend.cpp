#include "silhouette_blend.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "cloth_bsdf.hpp"
#include "foldcast/core/colour.hpp"

namespace foldcast::render {
namespace {

// A pixel is on the silhouette when between kEdgeShare and 1 - kEdgeShare of its samples hit
// the garment and (almost) none its supports (the rod, the clips and wires have their own
// mixture weight in the passes).
constexpr float kEdgeShare = 0.02f;
constexpr float kSupportShare = 0.02f;
// Neighbours whose garment share differs by more than this are another mixture (the pure
// garment or backdrop beside the edge), not the silhouette's next pixel.  0.2 / 0.3 / 0.5:
// 320x180 squared error 23.66 / 23.55 / 23.51 (with kNoiseShare 0.5).
constexpr float kSameShare = 0.5f;
// How much of the pixel's variance (sample variance of its mean luminance) the difference
// may be and still be taken as noise: 0.25 / 0.5 / 1 (share tolerance 0.3): 23.64 / 23.55 /
// 23.61; the sample variance over-states the noise of a Sobol'-stratified mixture.
constexpr float kNoiseShare = 0.5f;
constexpr int kMinNeighbours = 2;

}  // namespace

void blend_silhouette(const SilhouetteInput& in, std::vector<float>& rgba) {
    const int w = in.width, h = in.height;
    const std::vector<float>& cloth = *in.cloth;
    const std::vector<float>& turning = *in.turning;
    const std::vector<std::int32_t>& covered = *in.covered;
    const auto silhouette_side = [&](std::size_t j) { return covered[j] && turning[j] - cloth[j] <= kSupportShare; };
    const std::vector<float> before = rgba;
    for (int y = 1; y + 1 < h; ++y)
        for (int x = 1; x + 1 < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            const float share = cloth[i];
            if (!(share > kEdgeShare && share < 1.0f - kEdgeShare) || !silhouette_side(i)) continue;
            V3 sum = V3::Zero();
            int n = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const std::size_t j = std::size_t(y + dy) * w + std::size_t(x + dx);
                    if (j == i || !silhouette_side(j) || std::abs(cloth[j] - share) > kSameShare) continue;
                    sum += V3(before[4 * j], before[4 * j + 1], before[4 * j + 2]);
                    ++n;
                }
            if (n < kMinNeighbours) continue;
            const V3 mean = sum / float(n), own(before[4 * i], before[4 * i + 1], before[4 * i + 2]);
            const float difference = luminance(mean) - luminance(own);
            const float k = std::min(1.0f, kNoiseShare * (*in.variance)[i] / (difference * difference + 1e-12f));
            for (int c = 0; c < 3; ++c) rgba[4 * i + c] = own[c] + k * (mean[c] - own[c]);
        }
}

}  // namespace foldcast::render
