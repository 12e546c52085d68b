#pragma once
// The denoiser's last stage on the cloth: a weighted first-order regression over each cloth
// pixel's neighbourhood (after Bitterli et al. 2016, "Nonlinearly Weighted First-order
// Regression for Denoising Monte Carlo Renderings").  The a-trous passes average a pixel only
// with neighbours whose shading normal agrees within cos^128, so on the folds, where the
// normal turns from one pixel to the next, they keep most of the noise.  Fitting the
// demodulated light as a linear function of the normal and the position instead lets every
// neighbour of the same cloth take part: the change of shading with the normal is in the
// model, not in the residual.  Measured in docs/benchmarks.md ("Cloth regression").
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cloth_bsdf.hpp"
#include "fit_input.hpp"

namespace foldcast::render {

// One image's inputs to the regression, one entry per pixel.
struct ClothRegressionInput : RegressionInput {
    const std::vector<std::int32_t>* cloth = nullptr;  // 1: most of the pixel's samples hit the garment
    // The depth's change and the offset's squares and product as further regressors, and a
    // looser depth weight (stills: 55 products a tap instead of 21, which turntable frames do
    // not spend).
    bool depth_regressor = false;
    // With the depth regressor: each pixel the mean of its own and its neighbours' fits
    // evaluated at it, not its own fit alone (stills: a second sweep of the window).
    bool average_fits = false;
    // With the depth regressor: where to write each cloth pixel's own fit as well (with
    // average_fits the halves' blend chooses between the two, fit_selection.hpp); null
    // for none.  Pixels whose own fit fails or does not fit keep what it holds.
    std::vector<V3>* own_fits = nullptr;
    // The window's Gaussian weights, in pixels (3 for turntable frames; a still's from
    // still_spatial_sigma below).
    float spatial_sigma = 3.0f;
};

// A still's spatial sigma from the number of its cloth pixels: the linear model holds over a
// fold's width, which on a garment covering fewer pixels is fewer pixels.  3 (chosen at
// 640x360, where the default scene's garment covers about 18 600 pixels) down to 1.5 for a
// garment a quarter that size (320x180): there, squared error at 16 spp + denoise, seeds 1-3,
// sigma 1 / 1.5 / 2 / 3: 25.1 / 24.1 / 24.3 / 25.1; at 640x360 sigma 2 / 3 / 4: 12.60 / 12.55 /
// 12.60 (docs/benchmarks.md, 2026-11-27).  Not above 3: the window is 9 x 9.
inline float still_spatial_sigma(std::size_t cloth_pixels) {
    return std::clamp(std::sqrt(float(cloth_pixels)) / 44.0f, 1.5f, 3.0f);
}

// For every cloth pixel, the regression's value at the pixel (with average_fits, the mean of
// its and its neighbours' fits there) written to `out` (demodulated);
// other pixels, and pixels whose fit fails or does not fit (its residual far beyond the
// light's noise: a highlight that is not linear in the normal), keep what `out` holds.  Each pixel depends only on
// the inputs: the same floats for any thread count.
void regress_cloth(const ClothRegressionInput& in, std::vector<V3>& out);

}  // namespace foldcast::render
