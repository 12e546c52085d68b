#pragma once
// Colour basics shared by looks, render and compare: the sRGB transfer curve (IEC 61966-2-1)
// and Rec.709 luminance of linear RGB.
#include <Eigen/Core>
#include <cmath>

namespace foldcast {

inline float srgb_to_linear(float encoded) {
    return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

inline float linear_to_srgb(float linear) {
    return linear <= 0.0031308f ? linear * 12.92f : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

inline float luminance(const Eigen::Vector3f& linear_rgb) {
    return 0.2126f * linear_rgb.x() + 0.7152f * linear_rgb.y() + 0.0722f * linear_rgb.z();
}

}  // namespace foldcast
