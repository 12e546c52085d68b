#pragma once
// A still's pixel split in two layers by what its camera rays hit first: at a silhouette or
// where a fold's front sheet hides the back one, a pixel's samples see two surfaces, and the
// means the denoiser is given (light, albedo, normal, depth) are a mixture that no neighbour
// resembles.  Kept per layer, each part can be denoised as the surface it is
// (mixed_pixels.hpp).  The first sample's surface is layer 0; a sample joins it when it hit
// the same kind of surface (garment, metal, wood, backdrop or sky) within kLayerDepthTolerance of
// the first sample's depth, else it joins layer 1.  Samples are added in a fixed order, so the
// split is the same for any thread count.
#include <cmath>

#include "path_integrator.hpp"

namespace foldcast::render {

// Relative depth: where a fold's front sheet hides the back one, the two lie 2-4% apart
// (default scene at 320x180, seed 1: the quartiles of its cloth-on-cloth pixels), while one
// sheet's depth changes from one pixel to the next by under 0.5% in 9 pixels of 10.
constexpr float kLayerDepthTolerance = 0.02f;

// The sums of one layer's samples.
struct LayerSums {
    V3 all = V3::Zero(), albedo = V3::Zero(), normal = V3::Zero();
    float depth = 0.0f;
    int n = 0, metal = 0;  // metal: samples on the rod or a wire
    void add(const PathSample& s) {
        ++n;
        metal += s.metal ? 1 : 0;
        all += s.radiance;
        albedo += s.albedo;
        normal += V3(s.shading_normal.x(), s.shading_normal.y(), s.shading_normal.z());
        depth += s.depth;
    }
};

// What a pixel keeps beyond PixelSums for its layers: the first sample's surface and the
// sums of the samples that are not on it (layer 0's are the pixel's sums less these).
struct PixelLayers {
    float first_depth = 0.0f;
    int first_kind = -1;  // -1: no sample yet
    LayerSums other;
    static constexpr int kMetal = 2;
    static int kind(const PathSample& s) {
        return s.depth <= 0.0f ? 0 : s.garment ? 1 : s.metal ? kMetal : s.turning ? 3 : 4;
    }
    // Either layer is mostly metal.
    bool metal() const { return first_kind == kMetal || 2 * other.metal > other.n; }
    // The samples saw two surfaces.
    bool mixed() const { return other.n > 0; }
    // Some sample saw the rod or a wire.
    bool any_metal() const { return first_kind == kMetal || other.metal > 0; }
    void add(const PathSample& s) {
        const int k = kind(s);
        if (first_kind < 0) first_kind = k, first_depth = s.depth;
        if (k != first_kind || std::abs(s.depth - first_depth) > kLayerDepthTolerance * first_depth) other.add(s);
    }
};

}  // namespace foldcast::render
