#pragma once
// The coarse first frame (format version 4, docs/fca-format.md "Preview packet"): frame 0
// on a coarse uniform grid of `levels` steps over the largest side of the bounds, each
// vertex predicted from its mesh neighbours (parallelogram rule), the residuals as int16
// in one zstd frame.  From 0.2 kB (a 128 x 128 garment hanging flat) to 17 kB (the same
// folded), it lets a player draw the garment long before data packet 0 (all keyframes,
// about a tenth of a file) arrives.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "container.hpp"

namespace foldcast::codec {

// Steps over the largest side: the preview is within sqrt(3)/2 of a step of frame 0
// (0.34 mm for a garment whose largest side is 0.8 m).
inline constexpr std::uint16_t kPreviewLevels = 2048;
inline constexpr std::uint16_t kMaxPreviewLevels = 16383;  // residuals fit int16

std::string preview_payload(const std::vector<Vec3f>& frame0, const Header& header, std::uint16_t levels = kPreviewLevels);
// Throws InputError (naming `what`) on a malformed payload.
std::vector<Vec3f> parse_preview(std::string_view payload, const Header& header, const std::string& what);

}  // namespace foldcast::codec
