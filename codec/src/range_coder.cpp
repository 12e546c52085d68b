#include "range_coder.hpp"

#include <bit>

namespace foldcast::codec {
namespace {
constexpr int kProbBits = 11;
constexpr int kAdapt = 5;
constexpr std::uint32_t kTop = 1u << 24;
}  // namespace

void RangeEncoder::shift_low() {
    if (low_ < 0xff000000ull || low_ > 0xffffffffull) {
        const auto carry = static_cast<std::uint8_t>(low_ >> 32);
        std::uint8_t temp = cache_;
        do {
            out_.push_back(static_cast<char>(static_cast<std::uint8_t>(temp + carry)));
            temp = 0xff;
        } while (--cache_size_ != 0);
        cache_ = static_cast<std::uint8_t>(low_ >> 24);
    }
    ++cache_size_;
    low_ = (low_ & 0x00ffffffull) << 8;
}

void RangeEncoder::bit(std::uint16_t& p, int b) {
    const std::uint32_t bound = (range_ >> kProbBits) * p;
    if (b == 0) {
        range_ = bound;
        p = static_cast<std::uint16_t>(p + (((1u << kProbBits) - p) >> kAdapt));
    } else {
        low_ += bound;
        range_ -= bound;
        p = static_cast<std::uint16_t>(p - (p >> kAdapt));
    }
    while (range_ < kTop) {
        range_ <<= 8;
        shift_low();
    }
}

void RangeEncoder::direct_bits(std::uint32_t value, int count) {
    for (int i = count - 1; i >= 0; --i) {
        range_ >>= 1;
        if ((value >> i) & 1u) low_ += range_;
        while (range_ < kTop) {
            range_ <<= 8;
            shift_low();
        }
    }
}

std::string RangeEncoder::finish() {
    for (int i = 0; i < 5; ++i) shift_low();
    return std::move(out_);
}

RangeDecoder::RangeDecoder(std::string_view bytes) : bytes_(bytes) {
    for (int i = 0; i < 5; ++i) code_ = (code_ << 8) | next();
}

int RangeDecoder::bit(std::uint16_t& p) {
    const std::uint32_t bound = (range_ >> kProbBits) * p;
    int b;
    if (code_ < bound) {
        range_ = bound;
        p = static_cast<std::uint16_t>(p + (((1u << kProbBits) - p) >> kAdapt));
        b = 0;
    } else {
        code_ -= bound;
        range_ -= bound;
        p = static_cast<std::uint16_t>(p - (p >> kAdapt));
        b = 1;
    }
    while (range_ < kTop) {
        range_ <<= 8;
        code_ = (code_ << 8) | next();
    }
    return b;
}

std::uint32_t RangeDecoder::direct_bits(int count) {
    std::uint32_t v = 0;
    for (int i = 0; i < count; ++i) {
        range_ >>= 1;
        const std::uint32_t b = code_ >= range_ ? 1u : 0u;
        if (b) code_ -= range_;
        v = (v << 1) | b;
        while (range_ < kTop) {
            range_ <<= 8;
            code_ = (code_ << 8) | next();
        }
    }
    return v;
}

// value 0: zero flag.  Otherwise sign, then class k = bit length of |value| (1..) coded in
// unary with one adaptive probability per step, then the k-1 bits below the leading one:
// the first two adaptive (they carry the distribution's shape), the rest direct.
void encode_integer(RangeEncoder& enc, IntegerModel& m, std::int64_t value) {
    enc.bit(m.zero, value != 0);
    if (value == 0) return;
    enc.bit(m.sign, value < 0);
    const std::uint64_t mag = value < 0 ? static_cast<std::uint64_t>(-value) : static_cast<std::uint64_t>(value);
    const int k = std::bit_width(mag);
    for (int c = 1; c < k; ++c) enc.bit(m.klass[static_cast<std::size_t>(c)], 1);
    enc.bit(m.klass[static_cast<std::size_t>(k)], 0);
    const int below = k - 1;
    const int adaptive = below < 2 ? below : 2;
    std::size_t node = 0;  // a two-level tree: the second bit's probability depends on the first
    for (int i = 0; i < adaptive; ++i) {
        const int b = static_cast<int>((mag >> (below - 1 - i)) & 1u);
        enc.bit(m.mantissa[static_cast<std::size_t>(k)][node], b);
        node = 1 + static_cast<std::size_t>(b);
    }
    const int rest = below - adaptive;
    if (rest > 0) {
        const std::uint64_t low = mag & ((std::uint64_t(1) << rest) - 1);
        if (rest > 32) {
            enc.direct_bits(static_cast<std::uint32_t>(low >> 32), rest - 32);
            enc.direct_bits(static_cast<std::uint32_t>(low), 32);
        } else {
            enc.direct_bits(static_cast<std::uint32_t>(low), rest);
        }
    }
}

bool decode_integer(RangeDecoder& dec, IntegerModel& m, std::int64_t& value) {
    if (!dec.bit(m.zero)) {
        value = 0;
        return true;
    }
    const bool negative = dec.bit(m.sign);
    int k = 1;
    while (dec.bit(m.klass[static_cast<std::size_t>(k)])) {
        if (++k > IntegerModel::kMaxClass) return false;
    }
    const int below = k - 1;
    const int adaptive = below < 2 ? below : 2;
    std::uint64_t mag = 1;
    std::size_t node = 0;
    for (int i = 0; i < adaptive; ++i) {
        const int b = dec.bit(m.mantissa[static_cast<std::size_t>(k)][node]);
        mag = (mag << 1) | static_cast<std::uint64_t>(b);
        node = 1 + static_cast<std::size_t>(b);
    }
    const int rest = below - adaptive;
    if (rest > 32) {
        mag = (mag << (rest - 32)) | dec.direct_bits(rest - 32);
        mag = (mag << 32) | dec.direct_bits(32);
    } else if (rest > 0) {
        mag = (mag << rest) | dec.direct_bits(rest);
    }
    value = negative ? -static_cast<std::int64_t>(mag) : static_cast<std::int64_t>(mag);
    return true;
}

}  // namespace foldcast::codec
