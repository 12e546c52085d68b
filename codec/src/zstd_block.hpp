#pragma once
// zstd frames inside .fca payloads (the header's topology, the coarse first frame).
#include <cstdint>
#include <string>
#include <string_view>

#include "byte_io.hpp"

namespace foldcast::codec {

// One zstd frame of `raw` (level 19: written once, read many times).
std::string zstd_pack(std::string_view raw);

// The frame `packed`, which must declare and hold exactly `expected` bytes.  It is
// decompressed into a buffer that grows with what zstd produces: a frame that only claims
// a large size costs nothing before its bytes prove it.  Failures name `block` through `r`.
std::string zstd_unpack(std::string_view packed, std::uint64_t expected, const ByteReader& r, const std::string& block);

}  // namespace foldcast::codec
