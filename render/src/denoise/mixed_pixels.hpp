#pragma once
// A still denoiser's last stage: pixels whose samples saw two surfaces (the garment's
// silhouette against the backdrop, a fold's front sheet over its back sheet) rebuilt from
// their two layers (pixel_layers.hpp).  Their averaged albedo, normal and depth match no
// neighbour, so the a-trous passes and the regressions leave most of their noise.  Each
// layer's light is instead fitted, to first order in the offset from the pixel, over the
// 7 x 7 neighbourhood's layers whose depth, normal and albedo match it: the other mixed
// pixels along the same edge (their own layers' noisy light, by their share of the samples)
// and, at kPureWeight, the pure pixels' denoised light.  The pixel is then
// share_0 * albedo_0 * light_0 + share_1 * albedo_1 * light_1; the shares, from the Sobol'
// pixel positions, are much less noisy than the light.  The garment's pure pixels beside a
// rebuilt one are refitted the same way, their own denoised light among the candidates.
// Pixels whose layers are mostly the rod's or a wire's metal are left alone: the metal's
// highlight changes too fast across the edge for neighbours to stand in (default scene,
// 320x180, seeds 1-3: rebuilding the wires' pixels too took the squared error from 22.14
// to 23.25 x1e-6; a prototype that also rebuilt the rod's took seed 1 from 21.6 to 24.9).
// Measured in docs/benchmarks.md ("Mixed pixels from two layers", "Mixed pixels: a
// first-order fit").
#include <vector>

#include "cloth_bsdf.hpp"
#include "foldcast/render/render.hpp"

namespace foldcast::render {

// For every covered pixel of `rgba` with two layers in `features`, the rebuilt colour; the
// others are left as they are.  `light`: the denoised light, demodulated (colour / the
// pixel's demodulation_divisor of its albedo).  Each pixel depends only on the inputs: the
// same floats for any thread count.
void rebuild_mixed_pixels(Image& rgba, const PixelFeatures& features, const std::vector<V3>& light);

}  // namespace foldcast::render
