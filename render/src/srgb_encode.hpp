#pragma once
// Linear radiance to 8-bit sRGB, as PNG output and the swatch sheet need it.
#include <cstdint>

namespace foldcast::render {

// The sRGB transfer function of IEC 61966-2-1, clamped to [0, 1], rounded to the nearest
// code.  Exactly the same codes as evaluating the formula with std::pow, without the pow:
// a table of the 255 thresholds where the code steps up, entered by the float's top bits.
// NaN encodes as 0.
std::uint8_t encode_srgb8(float linear);

// The formula itself, for the table's construction and for tests.
std::uint8_t encode_srgb8_by_formula(float linear);

}  // namespace foldcast::render
