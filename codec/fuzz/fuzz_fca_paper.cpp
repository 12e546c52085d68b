// libFuzzer target for the paper profile's packet decoder.  fuzz_fca_decode must first get a
// header and CRCs right by chance; here the target builds a valid container around the
// input so that every execution reaches the profile: byte 0 picks N (1..16), bytes 1-2 pick
// T (2..2049), and the rest is a sequence of data-packet payloads, each a u16 length (little
// endian) and that many bytes (the last one cut short by the input's end).  The harness adds
// sequence numbers, CRCs and the end packet.  Any result but a decode or an InputError (a
// crash, a sanitizer report, another exception, a huge allocation, a hang) is a bug.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "container.hpp"
#include "foldcast/codec.hpp"
#include "foldcast/core/error.hpp"

namespace {
std::string container_around(const std::uint8_t* data, std::size_t size) {
    using namespace foldcast::codec;
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
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 3) return 0;
    const std::string file = container_around(data, size);
    try {
        foldcast::codec::StreamingDecoder decoder("fuzz input", file.size());
        decoder.feed(file);
        if (decoder.status().header_ready) {
            const auto anim = decoder.animation();
            (void)anim;
        }
    } catch (const foldcast::InputError&) {
    }
    return 0;
}
