// Issue #17 item 3 and the .fca part of its battery: `foldcast decode` on mutated, truncated
// and lying .fca files of every profile, each under a CPU-time and memory cap, must end with
// exit 0 (a valid prefix) or exit 2 and one line naming the file: never a crash, a signal, a
// hang past the cap or another status.  Mutations come from a fixed seed, so a failure
// repeats.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "byte_io.hpp"
#include "container.hpp"
#include "crc32.hpp"
#include "foldcast/codec/codec.hpp"
#include "run_command.hpp"
#include "spawn.hpp"
#include "test_paths.hpp"

namespace foldcast {
namespace {
namespace fs = std::filesystem;

// 10 CPU seconds: a decode of these small files takes well under one (ten times that under
// the sanitizers); the paper decoder took 27 s on the 65,284-frame header before #17.
constexpr test::Limits kCap{10, 2ull << 30};

Animation wave(int nu, int nv, int frames) {
    Animation a;
    a.fps = 30.0;
    for (int j = 0; j + 1 < nv; ++j)
        for (int i = 0; i + 1 < nu; ++i) {
            const auto v = static_cast<std::uint32_t>(j * nu + i), w = static_cast<std::uint32_t>(nu);
            a.topology.triangles.push_back({v, v + 1, v + w});
            a.topology.triangles.push_back({v + 1, v + w + 1, v + w});
        }
    for (int t = 0; t < frames; ++t) {
        std::vector<Vec3f> f;
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i)
                f.emplace_back(0.1f * float(i), -0.1f * float(j), 0.02f * std::sin(0.7f * float(i) + 0.3f * float(t)));
        a.frames.push_back(std::move(f));
    }
    return a;
}

std::string encoded(codec::Profile profile, int nu, int nv, int frames) {
    codec::EncodeOptions o;
    o.profile = profile;
    return codec::encode(wave(nu, nv, frames), o);
}

struct Packet {
    std::size_t offset;  // of its length field
    std::size_t payload_size;
};

std::vector<Packet> packets(const std::string& file) {
    std::vector<Packet> list;
    std::size_t at = sizeof codec::kMagic;
    while (at + 9 <= file.size()) {
        std::uint32_t size = 0;
        std::memcpy(&size, file.data() + at, 4);
        if (at + 9 + size > file.size()) break;
        list.push_back({at, size});
        at += 9 + size;
    }
    return list;
}

// Recomputes a packet's CRC after its payload was changed, so the change reaches the parser
// behind the CRC check.
void fix_crc(std::string& file, const Packet& p) {
    const std::string_view type(file.data() + p.offset + 4, 1);
    const std::string_view payload(file.data() + p.offset + 5, p.payload_size);
    const std::uint32_t crc = codec::crc32(payload, codec::crc32(type));
    std::memcpy(file.data() + p.offset + 5 + p.payload_size, &crc, 4);
}

class FcaBattery : public ::testing::Test {
protected:
    void SetUp() override { dir_ = test::temp_dir(); }

    // Decodes `bytes` under the cap; returns the outcome after checking the contract.
    test::Outcome decode(const std::string& bytes, const std::string& label) {
        const fs::path in = dir_ / "in.fca";
        std::ofstream(in, std::ios::binary) << bytes;
        const test::Outcome o =
            test::run_child({test::foldcast_under_test(), "decode", in.string(), "-o", (dir_ / "out.pc2").string()},
                            dir_ / "stderr.txt", kCap);
        EXPECT_TRUE(o.exited) << label << ": killed by signal " << o.signal << " after " << o.seconds << " s";
        EXPECT_TRUE(o.exit_code == 0 || o.exit_code == 2) << label << ": exit " << o.exit_code << ": " << o.err;
        if (o.exit_code == 2) {
            EXPECT_EQ(o.err.rfind("foldcast: ", 0), 0u) << label << ": " << o.err;
            EXPECT_EQ(o.err.find('\n'), o.err.size() - 1) << label << ": more than one line: " << o.err;
            EXPECT_NE(o.err.find(in.string()), std::string::npos)
                << label << ": the message does not name the file: " << o.err;
        }
        return o;
    }

    fs::path dir_;
};

TEST_F(FcaBattery, MutatedAndTruncatedFilesOfEveryProfile) {
    std::mt19937 rng(17);
    for (codec::Profile profile : {codec::Profile::paper, codec::Profile::predictive, codec::Profile::cascade}) {
        const std::string good = encoded(profile, 6, 5, 40);
        const std::vector<Packet> list = packets(good);
        ASSERT_GE(list.size(), 2u);
        const std::string name = codec::profile_name(profile);
        EXPECT_EQ(decode(good, name + " intact").exit_code, 0);
        for (int k = 0; k < 24; ++k) {
            std::string bad = good;
            const Packet& p = list[rng() % list.size()];
            const int changes = 1 + static_cast<int>(rng() % 4);
            for (int c = 0; c < changes; ++c) {
                const std::size_t at = p.offset + 5 + (p.payload_size ? rng() % p.payload_size : 0);
                bad[at] = static_cast<char>(rng());
            }
            if (k % 2 == 0) fix_crc(bad, p);  // half reach the payload parsers
            decode(bad, name + " mutation " + std::to_string(k));
        }
        for (int k = 0; k < 8; ++k) {
            const std::size_t cut = rng() % good.size();
            decode(good.substr(0, cut), name + " truncated at " + std::to_string(cut));
        }
    }
}

// The 2,825-byte file of the issue: a paper-profile header whose frame count was raised to
// 65,284 (or 250,000) with its CRC fixed.  Building the wavelet cost O(T^2) before #17 (27 s,
// and over 60 s): it must now fail or finish within the cap.
TEST_F(FcaBattery, PaperHeaderClaimingManyFramesIsBoundedByItsBytes) {
    for (int vertices_across : {1, 3}) {
        const std::string good = encoded(codec::Profile::paper, vertices_across, 3, 30);
        const Packet header = packets(good).front();
        // Payload: version u16, profile u8, vertex count u32, frame count u32.
        for (std::uint32_t frames : {65284u, 250000u, 4000000u}) {
            std::string bad = good;
            std::memcpy(bad.data() + header.offset + 5 + 2 + 1 + 4, &frames, 4);
            fix_crc(bad, header);
            const test::Outcome o = decode(bad, std::to_string(frames) + " frames claimed");
            EXPECT_TRUE(o.exited) << "killed past the cap: the work is not bounded by the file's bytes";
        }
    }
}

// A zstd frame that declares `content_bytes` (frame header with an 8-byte content size, one
// segment) followed by `filler` bytes of empty raw blocks: it claims the size, holds nothing.
std::string zstd_claiming(std::uint64_t content_bytes, std::size_t filler) {
    std::string frame = {'\x28', '\xb5', '\x2f', '\xfd', '\xe0'};
    frame.append(reinterpret_cast<const char*>(&content_bytes), 8);
    frame.append(filler, '\0');
    return frame;
}

// A decode bomb: a predictive header (fields kept up to the metadata count, 0) whose
// topology block claims `raw_bytes` of triangles in a block of `block_bytes`.
std::string topology_bomb(std::uint64_t raw_bytes, std::size_t block_bytes) {
    const std::string good = encoded(codec::Profile::predictive, 6, 5, 10);
    const Packet header = packets(good).front();
    std::string payload = good.substr(header.offset + 5, 80);  // up to the triangle count
    const std::uint32_t triangles = static_cast<std::uint32_t>(raw_bytes / 12);
    const std::uint32_t vertices = triangles / 4 + 1, frames = 1;
    std::memcpy(payload.data() + 3, &vertices, 4);
    std::memcpy(payload.data() + 7, &frames, 4);
    payload.append(reinterpret_cast<const char*>(&triangles), 4);
    payload.push_back('\0');  // no UVs
    payload += zstd_claiming(std::uint64_t(triangles) * 12, block_bytes);
    std::string file(codec::kMagic, sizeof codec::kMagic);
    codec::append_packet(file, codec::PacketType::header, payload);
    file += good.substr(header.offset + 9 + header.payload_size);
    const std::uint64_t total = file.size();
    std::memcpy(file.data() + sizeof codec::kMagic + 5 + 43, &total, 8);
    fix_crc(file, packets(file).front());
    return file;
}

// Decoding must be bounded by the bytes that are there: a 131 KB (197 KB) file whose header
// claims 2 GB (3 GB) of topology made the decoder allocate that much before decompressing
// anything (std::bad_alloc, exit 1, under this cap); one claiming 250 MB, within the format's
// limits, must fail on its missing bytes without allocating the claim.
TEST_F(FcaBattery, TopologyBlockClaimingHugeSizeIsBoundedByItsBytes) {
    const std::vector<std::pair<std::uint64_t, std::size_t>> claims = {
        {2'000'000'000, 131'000}, {3'100'000'000, 197'000}, {250'000'000, 20'000}};
    for (const auto& [raw, block] : claims) {
        const test::Outcome o = decode(topology_bomb(raw, block), std::to_string(raw) + " bytes of topology claimed");
        EXPECT_EQ(o.exit_code, 2) << o.err;
    }
}

}  // namespace
}  // namespace foldcast
