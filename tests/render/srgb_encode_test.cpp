// The table-driven sRGB encoder gives exactly the codes of the formula it replaced.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "srgb_encode.hpp"

namespace foldcast::render {
namespace {

TEST(SrgbEncode, MatchesTheFormulaAcrossTheUnitInterval) {
    const std::uint32_t one = std::bit_cast<std::uint32_t>(1.0f);
    std::uint64_t checked = 0;
    for (std::uint32_t bits = 0; bits <= one; bits += 97, ++checked) {
        const float x = std::bit_cast<float>(bits);
        ASSERT_EQ(encode_srgb8(x), encode_srgb8_by_formula(x)) << "at " << x;
    }
    EXPECT_GT(checked, 10'000'000u);
}

TEST(SrgbEncode, EveryCodeStepsUpAtTheSameFloat) {
    // Walk up from 0 one code at a time: at each step the float below the formula's step
    // encodes to the lower code and the step itself to the higher, in both encoders.
    float x = 0.0f;
    for (int code = 1; code < 256; ++code) {
        float lo = x, hi = 1.0f;
        while (std::nextafter(lo, 2.0f) < hi) {
            const float mid =
                std::bit_cast<float>((std::bit_cast<std::uint32_t>(lo) + std::bit_cast<std::uint32_t>(hi)) / 2);
            (encode_srgb8_by_formula(mid) >= code ? hi : lo) = mid;
        }
        EXPECT_EQ(encode_srgb8(lo), code - 1) << "below the step to " << code;
        EXPECT_EQ(encode_srgb8(hi), code) << "at the step to " << code;
        x = hi;
    }
}

TEST(SrgbEncode, OutOfRangeValuesClamp) {
    EXPECT_EQ(encode_srgb8(-1.0f), 0);
    EXPECT_EQ(encode_srgb8(-0.0f), 0);
    EXPECT_EQ(encode_srgb8(std::numeric_limits<float>::quiet_NaN()), 0);
    EXPECT_EQ(encode_srgb8(1.0f), 255);
    EXPECT_EQ(encode_srgb8(7.5f), 255);
    EXPECT_EQ(encode_srgb8(std::numeric_limits<float>::infinity()), 255);
    EXPECT_EQ(encode_srgb8(0.5f), 188);  // (1.055 * 0.5^(1/2.4) - 0.055) * 255 = 187.52
}

}  // namespace
}  // namespace foldcast::render
