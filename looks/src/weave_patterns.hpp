#pragma once
// Unfiltered yarn geometry of each procedural structure, in yarn units (1 = repeat_mm).
// weave.cpp filters these by the pixel footprint.
#include <Eigen/Core>

#include "foldcast/looks/looks.hpp"

namespace foldcast::looks::detail {

enum class Pattern { plain, twill_2_1, twill_3_1, satin_5, jersey, count };

Pattern pattern_of(const Appearance& appearance);  // Weave::none has no pattern: don't call
Eigen::Vector2i pattern_period_yarns(Pattern pattern);

struct YarnPoint {
    float albedo = 1.0f;   // un-normalised shading of the yarn surface (edges darker)
    float slope_u = 0.0f;  // d(height)/du of the yarn surface, height and u in the same units
    float slope_v = 0.0f;
    float weft = 0.0f;  // 1 where weft is on top
    int yarn = 0;       // 0 gap, 1 yarn along u (warp) on top, 2 yarn along v on top
};

// x = u / pitch, y = v / pitch.
YarnPoint evaluate_pattern(Pattern pattern, double x, double y);

}  // namespace foldcast::looks::detail
