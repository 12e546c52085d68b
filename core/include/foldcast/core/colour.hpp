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

// Rec.709's weights of linear R, G and B in luminance (for code that weighs many pixels at once).
constexpr float kLuminanceWeights[3] = {0.2126f, 0.7152f, 0.0722f};

inline float luminance(const Eigen::Vector3f& linear_rgb) {
    return kLuminanceWeights[0] * linear_rgb.x() + kLuminanceWeights[1] * linear_rgb.y() +
           kLuminanceWeights[2] * linear_rgb.z();
}

}  // namespace foldcast
