#pragma once
// Little-endian byte writer and a bounds-checked reader.  Every read from a file goes
// through ByteReader, so a hostile length or count can never read past the bytes we hold:
// it throws InputError naming what was being read instead.
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "foldcast/core/error.hpp"

namespace foldcast::codec {

class ByteWriter {
public:
    template <typename T>
    void put(T value) {
        char raw[sizeof(T)];
        std::memcpy(raw, &value, sizeof(T));
        bytes_.append(raw, sizeof(T));
    }
    void put_bytes(std::string_view b) { bytes_.append(b); }
    // LEB128-style unsigned varint: small counts cost one byte.
    void put_varint(std::uint64_t v) {
        while (v >= 0x80) {
            bytes_.push_back(static_cast<char>((v & 0x7f) | 0x80));
            v >>= 7;
        }
        bytes_.push_back(static_cast<char>(v));
    }
    std::string& bytes() { return bytes_; }
    std::size_t size() const { return bytes_.size(); }

private:
    std::string bytes_;
};

class ByteReader {
public:
    ByteReader(std::string_view bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}

    template <typename T>
    T get(const char* field) {
        need(sizeof(T), field);
        T value;
        std::memcpy(&value, bytes_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        return value;
    }
    std::string_view get_bytes(std::size_t n, const char* field) {
        need(n, field);
        std::string_view out = bytes_.substr(pos_, n);
        pos_ += n;
        return out;
    }
    std::uint64_t get_varint(const char* field) {
        std::uint64_t v = 0;
        for (int shift = 0; shift < 64; shift += 7) {
            const auto byte = static_cast<std::uint8_t>(get<char>(field));
            v |= std::uint64_t(byte & 0x7f) << shift;
            if (!(byte & 0x80)) return v;
        }
        throw InputError(what_ + ": malformed varint in " + field);
    }
    std::size_t remaining() const { return bytes_.size() - pos_; }
    std::size_t position() const { return pos_; }
    const std::string& what() const { return what_; }
    [[noreturn]] void fail(const std::string& message) const { throw InputError(what_ + ": " + message); }
    void expect_end(const char* block) const {
        if (remaining() != 0)
            fail(std::string(block) + " has " + std::to_string(remaining()) + " unexpected trailing bytes");
    }

private:
    void need(std::size_t n, const char* field) const {
        if (n > remaining())
            fail(std::string("truncated while reading ") + field + " (needs " + std::to_string(n) + " bytes, " +
                 std::to_string(remaining()) + " left)");
    }
    std::string_view bytes_;
    std::size_t pos_ = 0;
    std::string what_;
};

}  // namespace foldcast::codec
