#pragma once
// The line in the chromaticity plane (r, g) = (R, G) / (R + G + B), linear light, from white
// through a colour's chromaticity.  Shading scales R, G and B alike and leaves a colour where
// it is on this line; light bounced between a fold's walls moves it further out, a highlight
// (the light's own white mixed in) moves it towards white.  The print test, the sheen test
// (fold_detection.cpp) and the cloth mask's colour region (cloth_mask.cpp) all measure
// against it.
#include <cmath>

namespace foldcast::compare::detail {

inline constexpr float kWhiteChromaticity = 1.0f / 3.0f;

struct HueLine {
    float ur = 0.0f, ug = 0.0f;  // unit direction from white (0 when the colour is white)
    float length = 0.0f;         // how far the colour lies from white

    HueLine(float r, float g) : length(std::hypot(r - kWhiteChromaticity, g - kWhiteChromaticity)) {
        if (length > 0.0f) ur = (r - kWhiteChromaticity) / length, ug = (g - kWhiteChromaticity) / length;
    }
    // Signed distance of (r, g) from white along the line (the colour itself: `length`).
    float along(float r, float g) const { return (r - kWhiteChromaticity) * ur + (g - kWhiteChromaticity) * ug; }
    // Distance of (r, g) from the line.
    float across(float r, float g) const {
        return std::abs((r - kWhiteChromaticity) * ug - (g - kWhiteChromaticity) * ur);
    }
};

}  // namespace foldcast::compare::detail
