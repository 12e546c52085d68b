#pragma once
// Procedural woven and knitted fabric structure at physical scale, for render's texture
// hook.  Pure functions of material coordinates, deterministic, band-limited by the pixel
// footprint so distant cloth fades to the weave's average instead of shimmering.
//
// Geometry (docs/looks.md, "Procedural weaves"): yarns are `repeat_mm` apart; warp yarns run
// along u, weft yarns along v.  One repeat of the pattern spans, in yarns (u x v):
// plain 2 x 2, twill k/1 (k = twill_float) (k+1) x (k+1) with a one-yarn diagonal shift,
// 5-harness satin 5 x 5 (move number 2), jersey knit 1 x 1 (one V loop per wale and course).
#include <Eigen/Core>

#include "foldcast/looks/looks.hpp"

namespace foldcast::looks {

struct WeaveSample {
    float albedo_scale = 1.0f;                 // multiplies the yarn colour (weave_albedo)
    Eigen::Vector3f normal{0.0f, 0.0f, 1.0f};  // tangent space: x along warp (u), y along weft (v)
    int yarn = 0;                              // 0 none/gap/mixed, 1 warp on top, 2 weft on top
    float weft_cover = 0.0f;                   // share of weft yarn showing here (filtered), for weft_colour
    // Variance of the surface slope that the footprint filter averaged away (0 when the
    // pixel resolves the yarns); a renderer may widen its specular lobe by it (Toksvig/LEAN).
    float slope_variance = 0.0f;
};

// uv_m: material coordinates in metres (foldcast garments' UVs); footprint_m: the width on
// the cloth covered by one pixel (0 = unfiltered).
WeaveSample sample_weave(const Appearance& appearance, Eigen::Vector2d uv_m, double footprint_m);

// The colour to shade with: base (warp) and weft colours mixed by weft_cover, times
// albedo_scale.
Eigen::Vector3f weave_albedo(const Appearance& appearance, const WeaveSample& sample);

// One repeat of the weave in yarns along u and v (1 x 1 for Weave::none); multiply by
// repeat_mm for millimetres.
Eigen::Vector2i weave_period_yarns(const Appearance& appearance);

}  // namespace foldcast::looks
