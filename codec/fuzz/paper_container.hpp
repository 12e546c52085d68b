#pragma once
// The container fuzz_fca_paper builds around its input (shared with the seed test): byte 0
// picks N (1..16), bytes 1-2 pick T (2..2049), the rest is a sequence of data-packet
// payloads, each a u16 length (little endian) and that many bytes, the last one cut short by
// the input's end.  Sequence numbers, CRCs, the header and the end packet are added here.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "container.hpp"

namespace foldcast::codec::fuzz {

inline std::string paper_container(const std::uint8_t* data, std::size_t size) {
    Header h;
    h.profile = Profile::paper;
    h.vertices = 1 + data[0] % 16;
    h.frames = 2 + (static_cast<std::uint32_t>(data[1]) | static_cast<std::uint32_t>(data[2]) << 8) % 2048;
    h.bounds.min = foldcast::Vec3f(-1.0f, -1.0f, -1.0f);
    h.bounds.max = foldcast::Vec3f(1.0f, 1.0f, 1.0f);
    h.step = 1e-3;
    std::string body;
    std::uint32_t sequence = 0;
    for (std::size_t at = 3; at < size; ++sequence) {
        std::size_t length = data[at];
        if (at + 1 < size) length |= std::size_t(data[at + 1]) << 8;
        at += 2;
        length = std::min(length, size > at ? size - at : 0);
        std::string payload(4, '\0');
        std::memcpy(payload.data(), &sequence, 4);
        payload.append(reinterpret_cast<const char*>(data) + std::min(at, size), length);
        append_packet(body, PacketType::data, payload);
        at += length;
    }
    std::string end(4, '\0');
    std::memcpy(end.data(), &sequence, 4);
    append_packet(body, PacketType::end, end);
    h.total_bytes = 0;
    h.total_bytes = sizeof(kMagic) + kPacketOverhead + header_payload(h).size() + body.size();
    std::string file(kMagic, sizeof(kMagic));
    append_packet(file, PacketType::header, header_payload(h));
    return file + body;
}

}  // namespace foldcast::codec::fuzz
