#pragma once
// Procedural woven and knitted fabric structure at physical scale, for render's texture
// hook.  Pure functions of material coordinates, deterministic, band-limited by the pixel
// footprint so distant cloth fades to the weave's average instead of shimmering.
#include <Eigen/Core>

#include "foldcast/looks.hpp"

namespace foldcast::looks {

struct WeaveSample {
    float albedo_scale = 1.0f;              // multiplies the base colour
    Eigen::Vector3f normal{0.0f, 0.0f, 1.0f};  // tangent space: x along warp (u), y along weft (v)
    int yarn = 0;                           // 0 none/gap, 1 warp on top, 2 weft on top
};

// uv_m: material coordinates in metres (foldcast garments' UVs); footprint_m: the width on
// the cloth covered by one pixel (0 = unfiltered).
WeaveSample sample_weave(const Appearance& appearance, Eigen::Vector2d uv_m, double footprint_m);

}  // namespace foldcast::looks
