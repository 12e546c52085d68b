#include "crc32.hpp"

#include <zlib.h>

namespace foldcast::codec {

std::uint32_t crc32(std::string_view bytes, std::uint32_t crc) {
    // zlib's is the same CRC, computed many bytes at a time (a byte-wise table loop took
    // 3 % of decoding).
    return static_cast<std::uint32_t>(
        crc32_z(crc, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<z_size_t>(bytes.size())));
}

}  // namespace foldcast::codec
