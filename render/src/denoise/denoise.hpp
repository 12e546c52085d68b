#pragma once
// A feature-guided a-trous denoiser (Dammertz et al. 2010, with SVGF's variance-guided
// colour weight, Schied et al. 2017) for stills and turntable frames.
//
// The colour is first divided by the first-hit albedo, so the weave, the print and every
// other texture detail stay out of the filter and are multiplied back afterwards; the
// remaining illumination is smoothed by five 3x3 a-trous passes (steps 1, 2, 4, 8, 16)
// whose weights stop at changes of the shading normal (the weave's bump included), of depth
// and of the illumination beyond what the pixel's own noise explains.  Where the tracer kept
// two half buffers (the first half of each pixel's samples and the rest), the first three
// passes cross-filter them (Rousselle et al. 2012): each half is averaged with colour
// weights taken from the other, so a pixel's noise does not decide whether that noise is
// kept; the halves are then merged and, after the last two passes, one more pass at step 1
// is guided by the merged light.  Last, every cloth pixel's light is fitted afresh from its
// neighbourhood's (a quarter the noisy light, the rest the passes' result) as a linear
// function of the normal and the position (cloth_light_fit.hpp), with the passes' result
// deciding which neighbours lie across a shadow's edge, and, in a still, every backdrop
// pixel's from the same blend over a wider window as a linear function of the position and
// the depth (backdrop_light_fit.hpp), and every pixel of the garment's supports (the rod,
// clips, wires) from the same blend along the support's axis (support_light_fit.hpp).  A
// still with half buffers runs the cloth's and the backdrop's regressions under two settings
// and blends them per pixel by weights fitted to the halves (fit_selection.hpp).  After
// the albedo is multiplied back, a still's pixels that saw two surfaces (a silhouette, a
// fold's front over its back) are rebuilt from the tracer's two layers (mixed_pixels.hpp).
// Each output pixel depends only on the inputs, so the result is the same for any thread
// count.
#include <vector>

#include "cloth_bsdf.hpp"
#include "foldcast/render/render.hpp"

namespace foldcast::render {

// A channel's albedo is divided out, but never less than this: the denoiser and the
// turntable's temporal filter demodulate alike.  The divisor is continuous in the albedo:
// velvet's dark green channel (0.005 diffuse) crosses 0.01 where its sheen rises with the view
// angle, and a divisor that jumped from the albedo to 1 there drew bright green contour lines
// (docs/benchmarks.md).
constexpr float kMinDemodulationAlbedo = 0.01f;
inline float demodulation_divisor(float albedo) {
    return albedo < kMinDemodulationAlbedo ? kMinDemodulationAlbedo : albedo;
}

// What a frame may spend on denoising.  A still takes the stages that a turntable's frames
// leave out so that the 36-frame 640x640 turntable stays within its 40 s (issue #16): the
// backdrop's regression (backdrop_light_fit.hpp; on frames it took that turntable's median
// from 38.8 s to 41.0 s), the cloth regression's depth regressor and window by the
// garment's size (cloth_light_fit.hpp), the supports' regression (support_light_fit.hpp)
// and the mixed pixels' rebuild from the tracer's two layers, which frames do not keep
// (mixed_pixels.hpp).  Frames keep the bytes they had without them.
enum class DenoiseBudget { frame, still };

// Denoises the RGB of an RGBA image in place (alpha is kept; pixels with alpha 0 are
// neither changed nor used), guided by the first-hit albedo, unit shading normal (zero for
// the sky), depth and luminance variance of `features` (the tracer's PixelFeatures), and
// cross-filtering its half buffers when it has them.
void denoise(Image& rgba, const PixelFeatures& features, int threads, DenoiseBudget budget);

}  // namespace foldcast::render
