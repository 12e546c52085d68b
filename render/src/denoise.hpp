#pragma once
// A feature-guided a-trous denoiser (Dammertz et al. 2010, with SVGF's variance-guided
// colour weight, Schied et al. 2017) for stills and turntable frames.
//
// The colour is first divided by the first-hit albedo, so the weave, the print and every
// other texture detail stay out of the filter and are multiplied back afterwards; the
// remaining illumination is smoothed by five 3x3 a-trous passes (steps 1, 2, 4, 8, 16)
// whose weights stop at changes of the shading normal (the weave's bump included), of depth
// and of the illumination beyond what the pixel's own noise explains.  Each output pixel
// depends only on the inputs, so the result is the same for any thread count.
#include <vector>

#include "cloth_bsdf.hpp"
#include "foldcast/render.hpp"

namespace foldcast::render {

// Per-pixel means over the pixel's samples, row-major like Image.
struct DenoiseFeatures {
    std::vector<V3> albedo;       // first-hit BSDF albedo
    std::vector<V3> normal;       // first-hit shading normal (sum; zero where the sky was seen)
    std::vector<float> depth;     // first-hit distance, 0 for the sky
    std::vector<float> variance;  // variance of the pixel's mean luminance
};

// Denoises the RGB of an RGBA image in place (alpha is kept; pixels with alpha 0 are
// neither changed nor used).
void denoise(Image& rgba, const DenoiseFeatures& features, int threads);

}  // namespace foldcast::render
