#pragma once
// Adaptive binary range coder (the LZMA construction: 11-bit probabilities adapting by
// 1/32, carry propagation through a cached byte) and an adaptive Exp-Golomb binarisation
// of signed integers.  The entropy stage of the default profile: unlike a static code,
// each context learns its own statistics as it goes (docs/codec.md).
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace foldcast::codec {

class RangeEncoder {
public:
    void bit(std::uint16_t& probability, int bit);
    void direct_bits(std::uint32_t value, int count);  // equiprobable
    std::string finish();

private:
    void shift_low();
    std::uint64_t low_ = 0;
    std::uint32_t range_ = 0xffffffffu;
    std::uint8_t cache_ = 0;
    std::uint64_t cache_size_ = 1;
    std::string out_;
};

class RangeDecoder {
public:
    explicit RangeDecoder(std::string_view bytes);
    int bit(std::uint16_t& probability);
    std::uint32_t direct_bits(int count);
    // True once the decoder has needed more bytes than it was given (corrupt/truncated).
    bool overrun() const { return pos_ > bytes_.size() + 4; }

private:
    std::uint8_t next() { return pos_ < bytes_.size() ? static_cast<std::uint8_t>(bytes_[pos_++]) : (++pos_, 0); }
    std::string_view bytes_;
    std::size_t pos_ = 0;
    std::uint32_t range_ = 0xffffffffu, code_ = 0;
};

// Probabilities for one context of signed integers: zero flag, sign, magnitude class
// (unary over bit lengths) and the two leading mantissa bits per class.
struct IntegerModel {
    static constexpr int kMaxClass = 40;
    std::uint16_t zero = 1024, sign = 1024;
    std::array<std::uint16_t, kMaxClass + 1> klass{};
    std::array<std::array<std::uint16_t, 3>, kMaxClass + 1> mantissa{};
    IntegerModel() {
        klass.fill(1024);
        for (auto& m : mantissa) m.fill(1024);
    }
};

void encode_integer(RangeEncoder& enc, IntegerModel& model, std::int64_t value);
// Returns false for a magnitude class past kMaxClass (only corrupt data produces one).
bool decode_integer(RangeDecoder& dec, IntegerModel& model, std::int64_t& value);

}  // namespace foldcast::codec
