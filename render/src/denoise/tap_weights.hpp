#pragma once
// The tap weights the denoiser's stages share (denoise.cpp's passes, cloth_light_fit.*,
// support_light_fit.*): a neighbour one stage refuses as another surface, mixture or light,
// the next refuses alike.

namespace foldcast::render {

// Taps weighted below exp(-kMaxExponent) are skipped: their weight (< 1e-9) is lost in the
// centre tap's.
inline constexpr float kMaxExponent = 20.0f;

// A pixel that is partly a thin wire or the rod's or the cloth's edge and partly backdrop
// (its share of samples on the garment and supports between 0 and 1) is not its neighbours'
// mixture: taps whose share differs by more than the dead zone (a 16-sample share's noise
// is about 0.1) are refused, exp(-kMixScale (|difference| - kMixDeadZone)).  Measured in
// docs/benchmarks.md ("The denoiser's mixture weight").
inline constexpr float kMixScale = 16.0f;
inline constexpr float kMixDeadZone = 0.2f;

// The regressions leave out taps of a much different albedo (a print, a trim, a clip's wood
// beside the rod; the demodulated light of cloth whose sheen and gloss weigh differently
// against its colour).  Not tighter: where the weave is resolved (the twill close-up)
// neighbouring threads differ in albedo, and a tight test left too few taps (twill SSIM 0.9978
// at 0.1 and 0.2, 0.9969 at 0.02, 0.9928 at 0.005).
inline constexpr float kRegressionSameAlbedo = 0.1f;

// The regressions' colour weight on the a-trous result's luminance, which keeps a shadow's or
// a highlight's edge from being fitted across: exp(-difference^2 / scale^2), scale^2 the sum of
// (kColourSigma standard deviations of the two guide pixels' noise)^2 and (kColourRelative of
// the pixel's light)^2.  Looser or tighter, the default scene's garment loses
// (docs/benchmarks.md).
inline constexpr float kColourSigma = 5.0f;
inline constexpr float kColourRelative = 0.05f;

}  // namespace foldcast::render
