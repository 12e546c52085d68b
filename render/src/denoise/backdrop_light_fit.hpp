#pragma once
// The denoiser's last stage on the backdrop: each backdrop pixel's light fitted as a linear
// function of the image position and the depth over a 21 x 21 window with Gaussian weights.
// The a-trous passes' colour weight leaves blotches a few pixels across on the flat backdrop;
// the backdrop's light is smooth on the surface, so a fit over a window wider than the
// blotches takes them out.  The weights depend only on the offset and on whether the tap is
// backdrop, so the fit's sums are separable (a row pass, then a column pass); where the same
// model does not fit the a-trous result (a shadow's edge), the fit is blended back to it.
// Measured in docs/benchmarks.md ("The backdrop's regression").
#include <cstdint>
#include <vector>

#include "cloth_bsdf.hpp"

namespace foldcast::render {

// One image's inputs, one entry per pixel.
struct BackdropRegressionInput {
    int width = 0, height = 0;
    const std::vector<V3>* light = nullptr;               // the light to fit, demodulated
    const std::vector<float>* guide = nullptr;            // luminance of the a-trous result
    const std::vector<float>* variance = nullptr;         // of the guide
    const std::vector<float>* depth = nullptr;            // first-hit depth
    const std::vector<std::int32_t>* backdrop = nullptr;  // 1: every sample hit the backdrop
};

// For every backdrop pixel, the fit blended into `out` (which holds the a-trous result,
// demodulated) by how well the same model fits the guide: exp(-the guide's weighted residual
// variance / (kMisfit times its noise)).  Other pixels keep what `out` holds.  Each pixel
// depends only on the inputs: the same floats for any thread count.
void regress_backdrop(const BackdropRegressionInput& in, std::vector<V3>& out);

}  // namespace foldcast::render
