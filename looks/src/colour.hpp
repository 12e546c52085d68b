#pragma once
// sRGB <-> linear conversions for look colours (IEC 61966-2-1 transfer curve).
#include <optional>
#include <string>
#include <string_view>

#include <Eigen/Core>

namespace foldcast::looks {

float srgb_to_linear(float encoded);
float linear_to_srgb(float linear);

// "#RRGGBB" (case-insensitive) -> linear RGB; nullopt if the text is not of that form.
std::optional<Eigen::Vector3f> parse_srgb_hex(std::string_view text);
// Linear RGB in [0,1] -> "#rrggbb" (rounded; for display).
std::string to_srgb_hex(const Eigen::Vector3f& linear);

}  // namespace foldcast::looks
