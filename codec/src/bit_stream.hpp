#pragma once
// Bit packing, most significant bit first: the Huffman codes of the `paper` profile, and
// the side information (frame modes, frequency tables) and raw mantissa bits of the
// default profile.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace foldcast::codec {

class BitWriter {
public:
    // The low `count` bits of `bits`, most significant first; count <= 32.
    void put(std::uint32_t bits, int count) {
        acc_ = (acc_ << count) | (count == 32 ? bits : (bits & ((1u << count) - 1u)));
        fill_ += count;
        while (fill_ >= 8) {
            fill_ -= 8;
            bytes_.push_back(static_cast<char>((acc_ >> fill_) & 0xffu));
        }
    }
    // Pads the last byte with zeros.
    std::string finish() {
        if (fill_ > 0) bytes_.push_back(static_cast<char>((acc_ << (8 - fill_)) & 0xffu));
        fill_ = 0;
        acc_ = 0;
        return std::move(bytes_);
    }

private:
    std::string bytes_;
    std::uint64_t acc_ = 0;
    int fill_ = 0;
};

// Reads past the end as zero bits and remembers that it did (corrupt or truncated data),
// so callers may check overrun() once after many reads.
class BitReader {
public:
    explicit BitReader(std::string_view bytes) : bytes_(bytes) {}
    // count <= 32.
    std::uint32_t get(int count) {
        const std::uint32_t bits = peek(count);
        skip(count);
        return bits;
    }
    // The next `count` bits (count <= 32) without consuming them: looking past the end is
    // no overrun, only consuming past it is.
    std::uint32_t peek(int count) {
        if (fill_ < count) [[unlikely]] {  // whole bytes up to 56 bits, so this is rare
            for (; fill_ <= 56; fill_ += 8, ++pos_)
                acc_ = (acc_ << 8) | (pos_ < bytes_.size() ? static_cast<std::uint8_t>(bytes_[pos_]) : 0u);
        }
        return static_cast<std::uint32_t>((acc_ >> (fill_ - count)) & ((std::uint64_t(1) << count) - 1));
    }
    // Consumes `count` bits, at most as many as the last peek looked at.
    void skip(int count) { fill_ -= count; }
    bool overrun() const { return bit_position() > 8 * bytes_.size(); }
    std::size_t bit_position() const { return 8 * pos_ - static_cast<std::size_t>(fill_); }
    std::string_view bytes() const { return bytes_; }

private:
    std::string_view bytes_;
    std::size_t pos_ = 0;  // bytes fetched, zeros past the end included
    std::uint64_t acc_ = 0;
    int fill_ = 0;
};

// The same bits read from a bit position of a copy padded with eight zero bytes: one
// unaligned load and no branch per read, for the many short raw fields of the default
// profile.  Reads past the end give zero bits (the position is clamped to the padding), and
// overrun() says whether any did.
class PaddedBitReader {
public:
    PaddedBitReader(std::string_view bytes, std::size_t bit_position, std::vector<std::uint8_t>& storage)
        : bits_(8 * bytes.size()), position_(bit_position) {
        storage.assign(bytes.begin(), bytes.end());
        storage.resize(bytes.size() + 8, 0);
        data_ = storage.data();
    }
    // 1 <= count <= 32.
    std::uint32_t get(int count) {
        std::uint64_t word;
        std::memcpy(&word, data_ + std::min(position_ >> 3, bits_ >> 3), sizeof word);
        if constexpr (std::endian::native == std::endian::little) word = __builtin_bswap64(word);
        word <<= position_ & 7;
        position_ += static_cast<std::size_t>(count);
        return static_cast<std::uint32_t>(word >> (64 - count));
    }
    bool overrun() const { return position_ > bits_; }

private:
    const std::uint8_t* data_;
    std::size_t bits_, position_;
};

}  // namespace foldcast::codec
