#pragma once
// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320, the one zlib and PNG use): each
// .fca packet carries it so corruption is detected before any payload is interpreted.
#include <cstdint>
#include <string_view>

namespace foldcast::codec {

std::uint32_t crc32(std::string_view bytes, std::uint32_t crc = 0);

}  // namespace foldcast::codec
