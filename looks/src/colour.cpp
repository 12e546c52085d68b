#include "colour.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include "foldcast/core/colour.hpp"

namespace foldcast::looks {

namespace {
int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}
}  // namespace

std::optional<Eigen::Vector3f> parse_srgb_hex(std::string_view text) {
    if (text.size() != 7 || text[0] != '#') return std::nullopt;
    Eigen::Vector3f linear;
    for (int channel = 0; channel < 3; ++channel) {
        const int high = hex_digit(text[1 + 2 * channel]);
        const int low = hex_digit(text[2 + 2 * channel]);
        if (high < 0 || low < 0) return std::nullopt;
        linear[channel] = srgb_to_linear(static_cast<float>(high * 16 + low) / 255.0f);
    }
    return linear;
}

std::string to_srgb_hex(const Eigen::Vector3f& linear) {
    int bytes[3];
    for (int channel = 0; channel < 3; ++channel) {
        const float encoded = linear_to_srgb(std::clamp(linear[channel], 0.0f, 1.0f));
        bytes[channel] = static_cast<int>(std::lround(encoded * 255.0f));
    }
    char text[8];
    std::snprintf(text, sizeof text, "#%02x%02x%02x", bytes[0], bytes[1], bytes[2]);
    return text;
}

}  // namespace foldcast::looks
