#pragma once
// A still's last stage: each cloth and backdrop pixel blended between two settings of its
// regression (cloth_light_fit.hpp, backdrop_light_fit.hpp) by weights fitted to the
// tracer's two half buffers (after Rousselle et al. 2012 and Bitterli et al. 2016).  No one
// setting is best everywhere: a wider window and more of the passes' result help flat cloth
// and blur folds.  Each setting is also run on either half alone; the halves' noise is
// independent, so E[(F(A) - B)^2] = MSE(F(A)) + var(B) with var(B) the same for any F, and the
// blend F0 + alpha (F1 - F0) whose halves come closest to the other half, over a small window
// (one pixel's difference is mostly noise), is the blend with the least error.  The cloth's
// blend of the two settings' averaged fits is blended again, the same way, with the same blend
// of each pixel's own fits (cloth_light_fit.hpp's average_fits and own_fits).  Measured in
// docs/benchmarks.md ("The regressions' settings blended per pixel by the halves").
#include <cstdint>
#include <vector>

#include "backdrop_light_fit.hpp"
#include "cloth_bsdf.hpp"
#include "cloth_light_fit.hpp"

namespace foldcast::render {

// One regression's setting: the share of the noisy light in what it fits (the rest the
// passes' result) and, for the cloth, its window's Gaussian sigma as a multiple of the
// still's (still_spatial_sigma).
struct RegressionSetting {
    float noisy_share, sigma_scale;
};
// The cloth's two: the still's window fitting the noisy light alone (its fits averaged over
// the window, cloth_light_fit.hpp, they are no longer blotchy), and twice that window fitting
// half of it (before the averaging: half in the still's window, three quarters in twice it).
// The backdrop's: a quarter of the noisy light (the single setting before, chosen against
// blotches at 1280x720 with adaptive sampling) and all of it.  Chosen on the default scene at
// 320x180 and checked at 640x360 (docs/benchmarks.md).
inline constexpr RegressionSetting kClothSettings[2] = {{1.0f, 1.0f}, {0.5f, 2.0f}};
inline constexpr RegressionSetting kBackdropSettings[2] = {{0.25f, 1.0f}, {1.0f, 1.0f}};

// What the passes made of one buffer (the whole pixel or one half), demodulated, one entry
// per pixel.
struct FilteredBuffer {
    const std::vector<V3>* noisy = nullptr;     // the buffer's light before the passes
    const std::vector<float>* noise = nullptr;  // the variance of its luminance
    const std::vector<V3>* filtered = nullptr;  // the passes' result
    const std::vector<float>* variance = nullptr;  // of the passes' result's luminance
};

// The still's inputs: the regressions' inputs whose light, guide and variances are set here
// from each buffer, the three buffers, and per channel how much a unit of demodulated
// light's error weighs in the image (albedo x the sRGB curve's slope, squared), so that the
// blend minimises the error as seen.
struct SelectionInput {
    ClothRegressionInput cloth;
    BackdropRegressionInput backdrop;
    FilteredBuffer whole, half_a, half_b;
    const std::vector<V3>* error_weight = nullptr;
};

// Writes both regressions' blends into `out` (which holds the whole buffer's passes' result,
// and may be `in.whole.filtered` itself); other pixels keep what it holds.  Each pixel depends only on the inputs: the same floats
// for any thread count.
void regress_still_by_halves(const SelectionInput& in, std::vector<V3>& out);

}  // namespace foldcast::render
