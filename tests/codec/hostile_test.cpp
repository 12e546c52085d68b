#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "container.hpp"
#include "crc32.hpp"
#include "foldcast/codec/codec.hpp"
#include "foldcast/core/error.hpp"
#include "test_animations.hpp"

namespace foldcast::codec {
namespace {

std::string small_file(Profile p) {
    EncodeOptions o;
    o.profile = p;
    return encode(test::wave_grid(5, 4, 20), o);
}

// Decoding must either succeed (a valid prefix) or throw InputError: never crash.
void decode_or_input_error(std::string_view bytes) {
    try {
        StreamingDecoder d("hostile", bytes.size());
        d.feed(bytes);
        if (d.status().header_ready) (void)d.animation();
    } catch (const InputError&) {
    }
}

TEST(Hostile, EveryFlippedByteIsDetectedOrHarmless) {
    for (Profile p : {Profile::paper, Profile::predictive}) {
        const std::string good = small_file(p);
        for (std::size_t i = 0; i < good.size(); ++i) {
            std::string bad = good;
            bad[i] = static_cast<char>(bad[i] ^ 0x5a);
            // Either an InputError, or (a flipped length field) a file that never completes.
            try {
                StreamingDecoder d("bad", bad.size());
                d.feed(bad);
                EXPECT_FALSE(d.status().complete) << "flip at " << i << " went unnoticed";
            } catch (const InputError&) {
            }
        }
    }
}

TEST(Hostile, CorruptedPacketPayloadThrowsNamingTheCrc) {
    std::string bad = small_file(Profile::predictive);
    bad[bad.size() - 20] = static_cast<char>(bad[bad.size() - 20] ^ 1);
    try {
        (void)decode(bad, "x.fca");
        FAIL() << "corruption not detected";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("CRC"), std::string::npos) << e.what();
    }
}

TEST(Hostile, NotAnFcaFile) {
    EXPECT_THROW((void)decode("POINTCACHE2 and more"), InputError);
    StreamingDecoder d("empty");
    d.feed("");
    EXPECT_FALSE(d.status().header_ready);
    EXPECT_THROW((void)d.animation(), InputError);
}

// A well-formed packet whose header claims more than the bytes can justify.
std::string file_with_header(Header h) {
    std::string f(kMagic, sizeof kMagic);
    append_packet(f, PacketType::header, header_payload(h));
    return f;
}

TEST(Hostile, HugeCountsAreRejectedBeforeAllocating) {
    Header h;
    h.vertices = 1u << 20;
    h.frames = 1u << 20;
    h.step = 1e-3;
    h.total_bytes = 1u << 20;
    EXPECT_THROW((void)decode(file_with_header(h)), InputError);
    h.vertices = 1000;
    h.frames = 100000;
    h.total_bytes = std::uint64_t(1) << 40;  // lies about the size: the real size bounds it
    EXPECT_THROW((void)decode(file_with_header(h)), InputError);
}

TEST(Hostile, OutOfRangeTriangleAndBadFieldsAreRejected) {
    Header h;
    h.vertices = 3;
    h.frames = 2;
    h.step = 1e-3;
    h.total_bytes = 1000;
    h.topology.triangles = {{0, 1, 7}};
    EXPECT_THROW((void)decode(file_with_header(h)), InputError);
    h.topology.triangles = {{0, 1, 2}};
    h.fps = -1.0;
    EXPECT_THROW((void)decode(file_with_header(h)), InputError);
    h.fps = 30.0;
    h.step = 0.0;
    EXPECT_THROW((void)decode(file_with_header(h)), InputError);
}

TEST(Hostile, PacketLengthBeyondDeclaredSizeIsRejected) {
    std::string f = small_file(Profile::paper);
    // Second packet's length field, right after the header packet.
    std::uint32_t header_len;
    std::memcpy(&header_len, f.data() + 8, 4);
    const std::size_t at = 8 + kPacketOverhead + header_len;
    const std::uint32_t huge = 1u << 29;
    std::memcpy(f.data() + at, &huge, 4);
    EXPECT_THROW((void)decode(f), InputError);
}

TEST(Hostile, RandomGarbageAfterValidHeaderNeverCrashes) {
    std::mt19937 rng(7);
    for (Profile p : {Profile::paper, Profile::predictive}) {
        const std::string good = small_file(p);
        std::uint32_t header_len;
        std::memcpy(&header_len, good.data() + 8, 4);
        const std::size_t keep = 8 + kPacketOverhead + header_len;
        for (int trial = 0; trial < 200; ++trial) {
            std::string bad = good.substr(0, keep);
            // A data packet with a valid CRC but random content.
            std::string payload(4 + rng() % 64, '\0');
            for (auto& c : payload) c = static_cast<char>(rng());
            std::memset(payload.data(), 0, 4);  // sequence 0
            append_packet(bad, PacketType::data, payload);
            decode_or_input_error(bad);
        }
    }
}

}  // namespace
}  // namespace foldcast::codec
