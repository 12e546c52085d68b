#include <gtest/gtest.h>

#include <cstring>
#include <iterator>
#include <fstream>
#include <nlohmann/json.hpp>

#include "foldcast/codec/codec.hpp"
#include "foldcast/core/mesh_io.hpp"
#include "run_command.hpp"
#include "test_paths.hpp"

namespace foldcast {
namespace {

// foldcast with `args`, stderr dropped.
test::CommandResult run(const std::string& args) {
    return test::run_command(test::foldcast_binary() + " " + args + " 2>/dev/null");
}

std::string q(const std::filesystem::path& p) {
    std::string quoted(1, '\'');
    quoted.append(p.string());
    quoted.push_back('\'');
    return quoted;
}

TEST(CodecCli, EncodeDecodeRoundTripThroughPc2AndObj) {
    const auto dir = test::temp_dir();
    const auto pc2 = test::test_data("animations/basicCloth.pc2");
    for (const char* profile : {"paper", "default"}) {
        const auto fca = dir / std::string(profile).append(".fca");
        const test::CommandResult enc = run("encode " + q(pc2) + " -o " + q(fca) + " --profile " +
                                            std::string(profile) + " --max-error-m 0.001 --json");
        ASSERT_EQ(enc.exit_code, 0) << enc.out;
        const auto j = nlohmann::json::parse(enc.out);
        for (const char* key : {"frames", "vertices", "bytes", "bpvf", "rms_error_rel", "max_error_rel", "kg_error"})
            EXPECT_TRUE(j.contains(key)) << key;
        EXPECT_EQ(j["frames"], 150);
        EXPECT_EQ(j["bytes"], std::filesystem::file_size(fca));
        EXPECT_LE(j["max_error_m"].get<double>(), 0.001 * 1.00001);

        const auto out = dir / std::string(profile).append(".pc2");
        const test::CommandResult dec = run("decode " + q(fca) + " -o " + q(out) + " --json");
        ASSERT_EQ(dec.exit_code, 0);
        const Animation original = read_pc2_animation(pc2, test::test_data("animations/basicCloth.obj"));
        const Animation back = read_pc2_animation(out, std::filesystem::path(out).replace_extension(".obj"));
        EXPECT_EQ(back.topology.triangles, original.topology.triangles);
        EXPECT_LE(codec::measure(original, back, 1).max_error_m, 0.001 * 1.00001);

        // Re-encoding an .fca works, and --frames selects a range.
        ASSERT_EQ(
            run("encode " + q(fca) + " -o " + q(dir / "again.fca") + " --profile " + std::string(profile)).exit_code,
            0);
        ASSERT_EQ(run("decode " + q(fca) + " -o " + q(dir / "part.pc2") + " --frames 10:20").exit_code, 0);
        EXPECT_EQ(read_pc2(dir / "part.pc2").size(), 10u);
    }
}

// The "done when": drape -> .fca -> decode -> .pc2 plays in Blender's Mesh Cache
// modifier.  No Blender here, so this checks the file against what Blender's PC2 reader
// (source/blender/modifiers/intern/MOD_meshcache_pc2.cc) accepts and how it reads frames:
// a 32-byte header "POINTCACHE2\0", int32 version 1, int32 vertex count equal to the mesh's
// (Blender's OBJ importer makes one mesh vertex per `v` line of a single object), float start,
// float sampling, int32 frame count > 0, then frame k's float32 xyz at 32 + 12 k N.
TEST(CodecCli, DrapeToFcaToPc2IsWhatBlendersMeshCacheReads) {
    const auto dir = test::temp_dir();
    const auto fca = dir / "anim.fca", pc2 = dir / "anim.pc2", obj = dir / "anim.obj";
    ASSERT_EQ(run("drape --grid 16x12 --frames 20 -o " + q(fca)).exit_code, 0);
    ASSERT_EQ(run("decode " + q(fca) + " -o " + q(pc2)).exit_code, 0);

    std::ifstream in(pc2, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GE(bytes.size(), 32u);
    EXPECT_EQ(std::string(bytes.data(), 12), std::string("POINTCACHE2\0", 12));
    auto i32 = [&](std::size_t at) {
        std::int32_t v;
        std::memcpy(&v, bytes.data() + at, 4);
        return v;
    };
    auto f32 = [&](std::size_t at) {
        float v;
        std::memcpy(&v, bytes.data() + at, 4);
        return v;
    };
    EXPECT_EQ(i32(12), 1);
    const std::int32_t verts = i32(16), frames = i32(28);
    EXPECT_EQ(f32(20), 0.0f);  // start
    EXPECT_EQ(f32(24), 1.0f);  // sampling: one cache frame per scene frame
    EXPECT_EQ(frames, 20);
    ASSERT_EQ(bytes.size(), 32u + std::size_t(frames) * std::size_t(verts) * 12u);

    std::ifstream obj_in(obj);
    int v_lines = 0, objects = 0;
    for (std::string line; std::getline(obj_in, line);) {
        v_lines += line.rfind("v ", 0) == 0;
        objects += line.rfind("o ", 0) == 0 || line.rfind("g ", 0) == 0;
    }
    EXPECT_EQ(v_lines, verts);
    EXPECT_LE(objects, 1);

    const Animation decoded = codec::decode(codec::read_fca(fca));
    ASSERT_EQ(decoded.frame_count(), std::size_t(frames));
    for (std::size_t k : {std::size_t(0), std::size_t(7), std::size_t(19)})
        for (std::size_t v = 0; v < decoded.vertex_count(); v += 37)
            for (int c = 0; c < 3; ++c)
                EXPECT_EQ(f32(32 + 12 * (k * std::size_t(verts) + v) + 4 * std::size_t(c)), decoded.frames[k][v][c]);
}

TEST(CodecCli, TopologyFlagAndTruncatedFileDecodesWithWarning) {
    const auto dir = test::temp_dir();
    std::filesystem::copy_file(test::test_data("animations/basicCloth.pc2"), dir / "cache.pc2");
    EXPECT_EQ(run("encode " + q(dir / "cache.pc2") + " -o " + q(dir / "a.fca")).exit_code, 2);  // no cache.obj
    ASSERT_EQ(run("encode " + q(dir / "cache.pc2") + " --topology " + q(test::test_data("animations/basicCloth.obj")) +
                  " -o " + q(dir / "a.fca"))
                  .exit_code,
              0);
    std::string bytes = codec::read_fca(dir / "a.fca");
    codec::write_fca(dir / "half.fca", std::string_view(bytes).substr(0, bytes.size() / 2));
    const test::CommandResult half = run("decode " + q(dir / "half.fca") + " -o " + q(dir / "half.pc2") + " --json");
    ASSERT_EQ(half.exit_code, 0);
    EXPECT_FALSE(nlohmann::json::parse(half.out)["complete"].get<bool>());
    EXPECT_EQ(read_pc2(dir / "half.pc2").size(), 150u);
}

// Bytes from the file's start to the end of packet k (0 = the header).
std::size_t end_of_packet(const std::string& fca, int k) {
    std::size_t at = 8;
    for (int i = 0; i <= k; ++i) {
        std::uint32_t length = 0;
        std::memcpy(&length, fca.data() + at, 4);
        at += 9 + length;
    }
    return at;
}

// A prefix with no frame in it is refused, naming the bytes the first frame needs; the
// frames of a longer prefix are real ones (never every vertex at one point), and the
// warning names only final frames.  The look the drape used is in the file's metadata.
TEST(CodecCli, PrefixWithoutAFrameIsRefusedAndTheLookIsStored) {
    const auto dir = test::temp_dir();
    const auto fca = dir / "d.fca";
    ASSERT_EQ(run("drape --grid 24x24 --frames 40 --sway-m 0.02 --look denim --quiet -o " + q(fca)).exit_code, 0);
    const std::string bytes = codec::read_fca(fca);
    const std::size_t preview_end = end_of_packet(bytes, 1), first_frame = end_of_packet(bytes, 2);
    const test::CommandResult json = run("decode " + q(fca) + " -o " + q(dir / "all.pc2") + " --json");
    ASSERT_EQ(json.exit_code, 0);
    EXPECT_EQ(nlohmann::json::parse(json.out)["metadata"]["look"], "denim");
    // Re-encoding keeps it.
    ASSERT_EQ(run("encode " + q(fca) + " -o " + q(dir / "again.fca")).exit_code, 0);
    EXPECT_EQ(nlohmann::json::parse(run("decode " + q(dir / "again.fca") + " -o " + q(dir / "again.pc2") + " --json").out)
                  ["metadata"]["look"],
              "denim");

    const auto decode_prefix = [&](std::size_t n) {
        codec::write_fca(dir / "p.fca", std::string_view(bytes).substr(0, n));
        std::filesystem::remove(dir / "p.pc2");
        return test::run_command(test::foldcast_binary() + " decode " + q(dir / "p.fca") + " -o " + q(dir / "p.pc2") +
                                 " 2>&1");
    };
    const std::string needs = "the first frame needs " + std::to_string(first_frame) + " bytes";
    for (const std::size_t n : {preview_end - 1, preview_end, first_frame - 1}) {
        const test::CommandResult r = decode_prefix(n);
        EXPECT_EQ(r.exit_code, 2) << n;
        EXPECT_NE(r.out.find(needs), std::string::npos) << r.out;
        EXPECT_NE(r.out.find(n >= preview_end ? "only a coarse preview of frame 0" : "hold no frame"), std::string::npos)
            << r.out;
        EXPECT_FALSE(std::filesystem::exists(dir / "p.pc2"));
    }
    const test::CommandResult r = decode_prefix(first_frame);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    // Data packet 0 holds the keyframes: frame 0 is final (and the warning says no more).
    EXPECT_NE(r.out.find("frames 0..0 are final"), std::string::npos) << r.out;
    const auto frames = read_pc2(dir / "p.pc2");
    ASSERT_EQ(frames.size(), 40u);
    const Bounds b = bounds(frames.back());
    EXPECT_GT((b.max - b.min).norm(), 0.1f) << "frames collapsed to a point";
}

TEST(CodecCli, ErrorsExitTwo) {
    const auto dir = test::temp_dir();
    const auto pc2 = q(test::test_data("animations/basicCloth.pc2"));
    EXPECT_EQ(run("encode " + q(dir / "missing.pc2") + " -o " + q(dir / "x.fca")).exit_code, 2);
    EXPECT_EQ(run("encode " + pc2 + " -o " + q(dir / "x.fca") + " --profile fast").exit_code, 2);
    EXPECT_EQ(run("encode " + pc2 + " -o " + q(dir / "x.fca") + " --max-error-m 0.1 --keep 0.5").exit_code, 2);
    EXPECT_EQ(run("encode " + pc2 + " -o " + q(dir / "x.fca") + " --keep 0.5").exit_code, 2);  // default profile
    EXPECT_EQ(run("encode " + pc2 + " -o " + q(dir / "x.fca") + " --profile paper --keep 2").exit_code, 2);
    EXPECT_EQ(run("encode " + pc2 + " -o " + q(dir / "x.pc2")).exit_code, 2);
    EXPECT_EQ(run("encode " + pc2).exit_code, 2);
    ASSERT_EQ(run("encode " + pc2 + " -o " + q(dir / "x.fca")).exit_code, 0);
    EXPECT_EQ(run("decode " + q(dir / "x.fca") + " -o " + q(dir / "y.pc2") + " --frames 5:500").exit_code, 2);
    EXPECT_EQ(run("decode " + q(dir / "x.fca") + " -o " + q(dir / "y.pc2") + " --frames abc").exit_code, 2);
    EXPECT_EQ(run("decode " + q(dir / "x.fca") + " -o " + q(dir / "y.obj")).exit_code, 2);
    std::string bytes = codec::read_fca(dir / "x.fca");
    codec::write_fca(dir / "head.fca", std::string_view(bytes).substr(0, 30));
    EXPECT_EQ(run("decode " + q(dir / "head.fca") + " -o " + q(dir / "y.pc2")).exit_code, 2);
    bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x40);
    codec::write_fca(dir / "bad.fca", bytes);
    EXPECT_EQ(run("decode " + q(dir / "bad.fca") + " -o " + q(dir / "y.pc2")).exit_code, 2);
    EXPECT_EQ(run("decode " + pc2 + " -o " + q(dir / "y.pc2")).exit_code, 2);  // not an .fca
    EXPECT_FALSE(std::filesystem::exists(dir / "y.pc2"));
}

// encode and decode both take -q/--quiet: decode then prints nothing on success (its .glb
// summary goes), while a truncated file's warning still reaches stderr.
TEST(CodecCli, DecodeQuietPrintsNothing) {
    const auto dir = test::temp_dir();
    const auto fca = dir / "q.fca";
    ASSERT_EQ(run("encode " + q(test::test_data("animations/basicCloth.pc2")) + " -o " + q(fca) + " --quiet").exit_code,
              0);
    const test::CommandResult loud = run("decode " + q(fca) + " -o " + q(dir / "loud.glb"));
    ASSERT_EQ(loud.exit_code, 0);
    EXPECT_FALSE(loud.out.empty());
    for (const char* flag : {"--quiet", "-q"}) {
        const test::CommandResult quiet = run("decode " + q(fca) + " -o " + q(dir / "quiet.glb") + " " + flag);
        ASSERT_EQ(quiet.exit_code, 0) << flag;
        EXPECT_EQ(quiet.out, "") << flag;
        EXPECT_TRUE(std::filesystem::exists(dir / "quiet.glb"));
    }
    const std::string bytes = codec::read_fca(fca);
    std::ofstream(dir / "half.fca", std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() / 2));
    const test::CommandResult half = test::run_command(test::foldcast_binary() + " decode " + q(dir / "half.fca") +
                                                       " -o " + q(dir / "half.pc2") + " --quiet 2>&1");
    ASSERT_EQ(half.exit_code, 0);
    EXPECT_NE(half.out.find("warning"), std::string::npos) << half.out;
}

}  // namespace
}  // namespace foldcast
