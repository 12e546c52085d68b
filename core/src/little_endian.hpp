#pragma once
// Values as the binary files foldcast writes and reads hold them (PLY's binary_little_endian,
// PC2): little-endian, which is every machine foldcast builds for, so the bytes are copied as
// they lie in memory.
#include <bit>
#include <cstring>
#include <ostream>

namespace foldcast::little_endian {
static_assert(std::endian::native == std::endian::little, "foldcast's binary files assume a little-endian machine");

template <typename T>
void put(std::ostream& out, T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out.write(bytes, sizeof(T));
}

template <typename T>
T get(const char* bytes) {
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
}
}  // namespace foldcast::little_endian
