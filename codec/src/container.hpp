#pragma once
// The .fca container (docs/fca-format.md): magic, then packets
//   u32 payload_bytes | u8 type | payload | u32 crc32(type, payload)
// The first packet is the header; data packets follow in streaming order; an end packet
// closes the file.  This file knows nothing about how a profile codes its data.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "foldcast/codec.hpp"
#include "foldcast/core/mesh.hpp"

namespace foldcast::codec {

inline constexpr char kMagic[8] = {'\x89', 'F', 'C', 'A', '\r', '\n', '\x1a', '\n'};
inline constexpr std::uint16_t kFormatVersion = 3;
inline constexpr std::size_t kPacketOverhead = 4 + 1 + 4;
inline constexpr std::uint32_t kMaxPayloadBytes = 1u << 30;
// Allocation policy: decoded vertex-frames may exceed the file's bytes by at most this
// factor, and never exceed kMaxVertexFrames.
inline constexpr std::uint64_t kMaxVertexFramesPerByte = 1u << 14;
inline constexpr std::uint64_t kMaxVertexFrames = std::uint64_t(1) << 28;

enum class PacketType : std::uint8_t { header = 1, data = 2, end = 3 };

struct Header {
    Profile profile = Profile::predictive;
    std::uint32_t vertices = 0, frames = 0;
    double fps = 30.0;
    Bounds bounds;
    Topology topology;
    std::uint64_t total_bytes = 0;  // of the whole file, as the encoder wrote it
    // Quantisation: step in coefficient (paper) or metres (default: the fine grid) units;
    // paper: the threshold eps; default: the closed-loop residual step m in grid units.
    double step = 0.0;
    double threshold = 0.0;
    std::uint32_t profile_param = 0;  // default: log2 of the keyframe stride; paper: 0
};

std::string header_payload(const Header& header);
// Validates every count against the payload size and the allocation policy (against
// `known_total_bytes` when given, else the size the header declares).
Header parse_header(std::string_view payload, const std::string& what, std::optional<std::uint64_t> known_total_bytes);

void append_packet(std::string& file, PacketType type, std::string_view payload);

}  // namespace foldcast::codec
