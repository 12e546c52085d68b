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

// Below this a channel's albedo is not divided out (the colour is filtered as it is): the
// denoiser and the turntable's temporal filter demodulate alike.
constexpr float kMinDemodulationAlbedo = 0.01f;
inline float demodulation_divisor(float albedo) { return albedo < kMinDemodulationAlbedo ? 1.0f : albedo; }

// Denoises the RGB of an RGBA image in place (alpha is kept; pixels with alpha 0 are
// neither changed nor used), guided by the first-hit albedo, unit shading normal (zero for
// the sky), depth and luminance variance of `features` (the tracer's PixelFeatures).
void denoise(Image& rgba, const PixelFeatures& features, int threads);

}  // namespace foldcast::render
