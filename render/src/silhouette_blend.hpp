#pragma once
// A still's last denoising step at the garment's silhouette.  A pixel partly garment and
// partly backdrop differs from every neighbour in its share of samples, its mean depth and
// its mean normal, so the a-trous passes and the regressions leave it as traced: at 320x180
// the default scene's silhouette kept its 16-spp noise (the denoised value equal to the raw
// one to three digits).  Here such a pixel moves towards the mean of its 3x3 neighbours of a
// similar share (also partly garment, along the silhouette) by as much as its own noise
// explains the difference, min(1, kNoiseShare * variance / difference^2): where the
// neighbours differ by far more than its noise (another mixture, a shading edge), it stays.
// Measured in docs/benchmarks.md ("Stills: ...", 2026-11-27).
#include <cstdint>
#include <vector>

namespace foldcast::render {

// One image's inputs, one entry per pixel.
struct SilhouetteInput {
    int width = 0, height = 0;
    const std::vector<float>* cloth = nullptr;           // share of the samples on the garment
    const std::vector<float>* turning = nullptr;         // ... on the garment or its supports
    const std::vector<float>* variance = nullptr;        // of the pixel's mean luminance
    const std::vector<std::int32_t>* covered = nullptr;  // alpha > 0
};

// Blends each silhouette pixel of `rgba` (RGBA, linear, the denoised image) as above; every
// other pixel, and alpha, keep their bytes.  It reads the image as it was before any pixel
// moved, so the result does not depend on the order or the thread count.
void blend_silhouette(const SilhouetteInput& in, std::vector<float>& rgba);

}  // namespace foldcast::render
