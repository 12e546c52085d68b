#pragma once
// Look colours as sRGB hex text (the transfer curve itself is in foldcast/core/colour.hpp).
#include <optional>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "foldcast/core/colour.hpp"

namespace foldcast::looks {

// "#RRGGBB" (case-insensitive) -> linear RGB; nullopt if the text is not of that form.
std::optional<Eigen::Vector3f> parse_srgb_hex(std::string_view text);
// Linear RGB in [0,1] -> "#rrggbb" (rounded; for display).
std::string to_srgb_hex(const Eigen::Vector3f& linear);

}  // namespace foldcast::looks
