#pragma once
// Plain bit packing, least significant bit first: the side information of a packet of the
// default profile (frame modes, frequency tables) and the raw mantissa bits of large
// residuals, which an entropy coder could not shrink.
#include <cstdint>
#include <string>
#include <string_view>

namespace foldcast::codec {

class BitWriter {
public:
    // `count` <= 32.
    void put(std::uint32_t value, int count) {
        buffer_ |= std::uint64_t(value & mask(count)) << filled_;
        filled_ += count;
        while (filled_ >= 8) {
            bytes_.push_back(static_cast<char>(buffer_ & 0xffu));
            buffer_ >>= 8;
            filled_ -= 8;
        }
    }
    std::string finish() {
        if (filled_ > 0) bytes_.push_back(static_cast<char>(buffer_ & 0xffu));
        buffer_ = 0;
        filled_ = 0;
        return std::move(bytes_);
    }

private:
    static std::uint32_t mask(int count) { return count >= 32 ? 0xffffffffu : (std::uint32_t(1) << count) - 1; }
    std::string bytes_;
    std::uint64_t buffer_ = 0;
    int filled_ = 0;
};

// Reads past the end as zero bits and remembers that it did (corrupt or truncated data):
// callers check overrun() once per frame instead of per read.
class BitReader {
public:
    explicit BitReader(std::string_view bytes) : bytes_(bytes) {}
    // `count` <= 32.
    std::uint32_t get(int count) {
        while (filled_ < count) {
            const std::uint64_t byte = pos_ < bytes_.size() ? static_cast<std::uint8_t>(bytes_[pos_]) : 0;
            ++pos_;
            buffer_ |= byte << filled_;
            filled_ += 8;
        }
        const auto value = static_cast<std::uint32_t>(buffer_ & ((std::uint64_t(1) << count) - 1));
        buffer_ >>= count;
        filled_ -= count;
        return value;
    }
    bool overrun() const { return pos_ > bytes_.size(); }

private:
    std::string_view bytes_;
    std::size_t pos_ = 0;
    std::uint64_t buffer_ = 0;
    int filled_ = 0;
};

}  // namespace foldcast::codec
