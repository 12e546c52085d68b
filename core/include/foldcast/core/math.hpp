#pragma once
// Numeric constants and unit conversions used by every module: one definition each.
#include <numbers>

namespace foldcast {

inline constexpr double kPi = std::numbers::pi;
inline constexpr float kPiF = std::numbers::pi_v<float>;

constexpr double deg_to_rad(double degrees) { return degrees * (kPi / 180.0); }
constexpr float deg_to_rad(float degrees) { return degrees * (kPiF / 180.0f); }

}  // namespace foldcast
