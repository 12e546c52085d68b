#pragma once
// The .fca container (docs/fca-format.md): magic, then packets
//   u32 payload_bytes | u8 type | payload | u32 crc32(type, payload)
// The first packet is the header; data packets follow in streaming order; an end packet
// closes the file.  This file knows nothing about how a profile codes its data.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "foldcast/codec/codec.hpp"
#include "foldcast/core/mesh.hpp"

namespace foldcast::codec {

inline constexpr char kMagic[8] = {'\x89', 'F', 'C', 'A', '\r', '\n', '\x1a', '\n'};
// Version 4 added the coarse first frame (the preview packet), the metadata and the
// header's first_frame_bytes; version 5 the isometric modes and weights of profile
// cascade, version 6 its escapes coded in context (predictive_profile.hpp); versions 3 to 5
// are still read.
inline constexpr std::uint16_t kFormatVersion = 6;
inline constexpr std::uint16_t kOldestReadableVersion = 3;
inline constexpr std::size_t kPacketOverhead = 4 + 1 + 4;
inline constexpr std::uint32_t kMaxPayloadBytes = 1u << 30;
// Allocation policy: decoded vertex-frames may exceed the file's bytes by at most this
// factor, and never exceed kMaxVertexFrames.  A perfectly still 128x128 grid over 2,000
// frames, the most compressible animation measured, holds 1,197 vertex-frames per byte.
inline constexpr std::uint64_t kMaxVertexFramesPerByte = 1u << 12;
inline constexpr std::uint64_t kMaxVertexFrames = std::uint64_t(1) << 28;
// The decoder keeps about 100 bytes per vertex while it decodes a packet and about 40 per
// frame of bookkeeping: these bound both whatever the file's size (8.4 M vertices: a
// 2,896 x 2,896 grid; 1 M frames: over 9 hours at 30 fps).
inline constexpr std::uint64_t kMaxVertices = std::uint64_t(1) << 23;
inline constexpr std::uint64_t kMaxFrames = std::uint64_t(1) << 20;
// The topology block (zstd): decompressed bytes per byte of the block at most this (a regular
// grid's triangles without UVs reach about 10,000), at most kMaxTrianglesPerVertex triangles
// per vertex (a cloth grid has 2), and at most kMaxTopologyBytes in all.
inline constexpr std::uint64_t kMaxTopologyBytesPerByte = 1u << 14;
inline constexpr std::uint64_t kMaxTrianglesPerVertex = 4;
inline constexpr std::uint64_t kMaxTopologyBytes = std::uint64_t(1) << 28;

// Metadata (version 4): at most this many entries, keys of 1..64 characters [a-z0-9_],
// values of at most 1,024 bytes without control characters.
inline constexpr std::size_t kMaxMetadataEntries = 32;
inline constexpr std::size_t kMaxMetadataKeyBytes = 64;
inline constexpr std::size_t kMaxMetadataValueBytes = 1024;
// What is wrong with `metadata` (empty: nothing); the encoder and the reader share it.
std::string metadata_problem(const Metadata& metadata);

enum class PacketType : std::uint8_t { header = 1, data = 2, end = 3, preview = 4 };

struct Header {
    std::uint16_t version = kFormatVersion;
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
    // Version 4: bytes from the file's start to the end of data packet 0 (what the first
    // final frame needs), and the metadata.
    std::uint64_t first_frame_bytes = 0;
    Metadata metadata;
};

std::string header_payload(const Header& header);
// Validates every count against the payload size and the allocation policy (against
// `known_total_bytes` when given, else the size the header declares).
Header parse_header(std::string_view payload, const std::string& what, std::optional<std::uint64_t> known_total_bytes);

void append_packet(std::string& file, PacketType type, std::string_view payload);

}  // namespace foldcast::codec
