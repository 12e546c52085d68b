#include "srgb_encode.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

namespace foldcast::render {

namespace {

// Floats below 2^-13 encode to 0 (the first step is at 0.5 / 255 / 12.92 = 1.5e-4).  From
// there to 1 each octave is cut into 64 buckets by its top mantissa bits; a bucket spans at
// most about 1.3 codes, so the code of its first float plus a step or two finds any code.
constexpr std::uint32_t kFirstBits = 114u << 23;  // 2^-13
constexpr int kBucketShift = 23 - 6;
constexpr std::uint32_t kOneBits = 127u << 23;
constexpr std::size_t kBuckets = ((kOneBits - kFirstBits) >> kBucketShift) + 1;

struct EncodeTables {
    // thresholds[k] = the smallest float that encodes to k or more; thresholds[256] = +inf.
    std::array<float, 257> thresholds{};
    std::array<std::uint8_t, kBuckets> bucket_code{};  // the code of each bucket's first float
};

// Non-negative floats order like their bit patterns, so bisection over the patterns finds
// each step exactly.
EncodeTables make_encode_tables() {
    EncodeTables t;
    for (int code = 1; code < 256; ++code) {
        std::uint32_t lo = 0, hi = kOneBits;  // encode(lo) < code <= encode(hi)
        while (hi - lo > 1) {
            const std::uint32_t mid = lo + (hi - lo) / 2;
            if (encode_srgb8_by_formula(std::bit_cast<float>(mid)) >= code)
                hi = mid;
            else
                lo = mid;
        }
        t.thresholds[static_cast<std::size_t>(code)] = std::bit_cast<float>(hi);
    }
    t.thresholds[256] = std::numeric_limits<float>::infinity();
    for (std::size_t b = 0; b < kBuckets; ++b)
        t.bucket_code[b] =
            encode_srgb8_by_formula(std::bit_cast<float>(kFirstBits + (static_cast<std::uint32_t>(b) << kBucketShift)));
    return t;
}

const EncodeTables encode_tables = make_encode_tables();

}  // namespace

std::uint8_t encode_srgb8_by_formula(float linear) {
    if (!(linear > 0.0f)) return 0;  // also NaN
    const float c = std::min(linear, 1.0f);
    const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
    return static_cast<std::uint8_t>(std::lround(s * 255.0f));
}

std::uint8_t encode_srgb8(float linear) {
    if (!(linear >= std::bit_cast<float>(kFirstBits))) return 0;  // also NaN
    if (linear >= 1.0f) return 255;
    std::size_t code = encode_tables.bucket_code[(std::bit_cast<std::uint32_t>(linear) - kFirstBits) >> kBucketShift];
    while (linear >= encode_tables.thresholds[code + 1]) ++code;
    return static_cast<std::uint8_t>(code);
}

}  // namespace foldcast::render
