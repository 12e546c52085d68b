#pragma once
// The denoiser's last stage on the garment's supports (the metal rod, the clips, the wires), in
// stills: each support pixel's light fitted from a line of pixels along the support.  A support
// is a thin cylinder a few pixels across: across it the normal turns through half a circle in
// two or three pixels and the rod's glossy highlight changes as fast, so the a-trous passes find
// few neighbours like a pixel there and keep much of its noise.  Along the axis the surface
// changes slowly, so each pixel's light is fitted as a quadratic in the offset along whichever
// image axis the support runs closer to (the one across which the normal and the coverage
// change less), over taps of the same support, albedo and coverage; where that fit does not
// follow the light (a highlight's edge crossing the line), the pixel is blended back to a
// straight line over its nearest taps along the axis, which follows a steep rise.  A pixel is
// fitted only where the support runs on along that axis for at least half the window, which
// leaves out the clips' short runs.  Measured in docs/benchmarks.md ("The supports'
// regression").
#include <cstdint>
#include <vector>

#include "cloth_bsdf.hpp"
#include "fit_input.hpp"

namespace foldcast::render {

// One image's inputs, one entry per pixel.
struct SupportRegressionInput : RegressionInput {
    const std::vector<float>* turning = nullptr;         // share of samples on the garment or its supports
    const std::vector<std::int32_t>* support = nullptr;  // 1: some samples hit a support, none the garment
};

// For every support pixel, the fit blended with the short line's (or, where that fails, with
// what `out` holds: the a-trous result, demodulated) by exp(-the fit's weighted residual
// variance / (kMisfit times the light's noise)), into `out`; other pixels, and those whose run along the axis is short or whose fit fails, keep
// what `out` holds.  Each pixel depends only on the inputs: the same floats for any thread count.
void regress_supports(const SupportRegressionInput& in, std::vector<V3>& out);

}  // namespace foldcast::render
