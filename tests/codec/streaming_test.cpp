#include <gtest/gtest.h>

#include "foldcast/codec/codec.hpp"
#include "foldcast/core/error.hpp"
#include "predictive_profile.hpp"
#include "test_animations.hpp"

namespace foldcast::codec {
namespace {

EncodeOptions profile_options(Profile p) {
    EncodeOptions o;
    o.profile = p;
    return o;
}

class Streaming : public ::testing::TestWithParam<Profile> {};

// Every prefix decodes (never throws) to an animation of the right shape; the error never
// grows as bytes arrive; frames reported playable are exactly the final ones.
TEST_P(Streaming, PrefixesDecodeCoarserAndErrorFallsAsBytesArrive) {
    // The default profile sends basicCloth (81 vertices) as one group: a 64x64 grid over
    // 160 frames makes five, so the error falls in several steps.
    const Animation a = GetParam() == Profile::paper ? test::basic_cloth() : test::wave_grid(64, 64, 160);
    const std::string bytes = encode(a, profile_options(GetParam()));
    const Animation full = decode(bytes);
    StreamingDecoder decoder("stream");
    double previous_error = std::numeric_limits<double>::infinity(), first_error = -1.0;
    std::size_t previous_playable = 0, previous_packets = 0, checked = 0;
    const std::size_t step = std::max<std::size_t>(1, bytes.size() / 97);
    for (std::size_t cut = 0; cut < bytes.size(); cut += step) {
        const std::size_t end = std::min(bytes.size(), cut + step);
        decoder.feed(std::string_view(bytes).substr(cut, end - cut));
        const StreamStatus s = decoder.status();
        EXPECT_GE(s.playable_frames, previous_playable);
        previous_playable = s.playable_frames;
        if (!s.frame_ready || s.packets == previous_packets) continue;
        previous_packets = s.packets;
        const Animation partial = decoder.animation();
        ASSERT_EQ(partial.frame_count(), a.frame_count());
        const double error = measure(a, partial, end).kg_error;
        // A newly arrived coefficient or frame carries quantisation error of its own, so
        // the error may rise by a hair (never by more than 0.1 %); otherwise it falls.
        EXPECT_LE(error, previous_error * (1.0 + 1e-3)) << "cut at " << end;
        previous_error = error;
        if (first_error < 0.0) first_error = error;
        for (std::size_t t = 0; t < s.playable_frames; ++t)
            ASSERT_EQ(partial.frames[t], full.frames[t]) << "frame " << t;
        // One frame alone (a player's access) is the same as in the whole animation, for
        // final and for interpolated frames alike.
        for (std::size_t t : {std::size_t(0), s.playable_frames, a.frame_count() / 2, a.frame_count() - 1})
            if (t < a.frame_count()) {
                ASSERT_EQ(decoder.frame(t), partial.frames[t]) << "frame " << t << ", cut at " << end;
            }
        ++checked;
    }
    EXPECT_GT(checked, 5u);
    EXPECT_LT(previous_error, first_error / 10.0);
    EXPECT_TRUE(decoder.status().complete);
    EXPECT_EQ(decoder.status().playable_frames, a.frame_count());
    EXPECT_EQ(decoder.animation().frames, full.frames);
}

TEST_P(Streaming, HalfAFileStillDecodesToSomethingClose) {
    const Animation a = test::basic_cloth();
    const std::string bytes = encode(a, profile_options(GetParam()));
    const Animation half = decode(std::string_view(bytes).substr(0, bytes.size() / 2));
    const Metrics m = measure(a, half, bytes.size() / 2);
    EXPECT_LT(m.kg_error, 100.0);  // much better than the per-frame mean
    EXPECT_LT(m.max_error_rel, 0.5);
}

TEST_P(Streaming, FrameAccessorMatchesAnimation) {
    const Animation a = test::wave_grid(6, 5, 30);
    const std::string bytes = encode(a, profile_options(GetParam()));
    StreamingDecoder d("s");
    d.feed(bytes);
    EXPECT_EQ(d.frame(17), d.animation().frames[17]);
    EXPECT_THROW(d.frame(30), InputError);
    EXPECT_EQ(d.vertex_count(), 30u);
    EXPECT_EQ(d.profile(), GetParam());
}

// The bound the header states is the one asked for (default profile) and holds on every
// final frame; paper states none.
TEST_P(Streaming, HeaderStatesTheErrorBoundOfFinalFrames) {
    const Animation a = test::wave_grid(16, 12, 40);
    EncodeOptions o = profile_options(GetParam());
    o.max_error_m = 1e-3;
    StreamingDecoder d("s");
    d.feed(encode(a, o));
    if (GetParam() == Profile::paper) {
        EXPECT_FALSE(d.max_error_m().has_value());
        return;
    }
    ASSERT_TRUE(d.max_error_m().has_value());
    EXPECT_NEAR(*d.max_error_m(), 1e-3, 1e-9);
    const Metrics m = measure(a, d.animation(), 0);
    EXPECT_LE(m.max_error_m, *d.max_error_m() * (1.0 + 1e-5));
}

// Decoding into an earlier animation's buffers gives the same frames, whatever that
// animation held, and overwrites buffers of the right size instead of allocating.
TEST_P(Streaming, DecodingIntoAnEarlierAnimationGivesTheSameFrames) {
    const Animation a = test::wave_grid(6, 5, 30);
    const std::string bytes = encode(a, profile_options(GetParam()));
    const Animation fresh = decode(bytes);
    for (Animation earlier : {test::basic_cloth(), test::wave_grid(6, 5, 12), fresh, Animation{}}) {
        decode(bytes, earlier);
        EXPECT_EQ(earlier.frames, fresh.frames);
        EXPECT_EQ(earlier.topology.triangles, fresh.topology.triangles);
        EXPECT_EQ(earlier.fps, fresh.fps);
    }
    if (GetParam() != Profile::paper) {
        Animation earlier = fresh;
        const Vec3f* buffer = earlier.frames[7].data();
        decode(bytes, earlier);
        EXPECT_EQ(earlier.frames[7].data(), buffer);
    }
}

// A corrupt packet fails the feed that completes it and stays failing; what was accepted
// before it is kept, and a whole-buffer decode into an animation leaves it empty.
TEST_P(Streaming, CorruptPacketIsReportedAgainAndEarlierPacketsKept) {
    const Animation a = test::basic_cloth();
    std::string bytes = encode(a, profile_options(GetParam()));
    bytes[bytes.size() - 40] = static_cast<char>(bytes[bytes.size() - 40] ^ 0x5a);
    StreamingDecoder d("s");
    EXPECT_THROW(d.feed(bytes), InputError);
    const std::size_t accepted = d.status().packets;
    EXPECT_GT(accepted, 1u);
    EXPECT_THROW(d.feed(""), InputError);
    EXPECT_EQ(d.status().packets, accepted);
    EXPECT_EQ(d.animation().frame_count(), a.frame_count());
    Animation out = a;
    EXPECT_THROW(decode(bytes, out), InputError);
    EXPECT_EQ(out.frame_count(), 0u);
}

// Before a group's packet arrives, its frames are the linear blend of the keyframes around
// them (the default profile's keyframes come first).
TEST(StreamingDefault, FramesBetweenKeyframesBlendThem) {
    // A grid large enough for keyframes every 16 frames (0, 16, 32, 39), however small
    // meshes are grouped.
    const std::size_t frames = 40;
    const Animation a = test::wave_grid(91, 91, static_cast<int>(frames));
    ASSERT_EQ(default_stride_log2(frames, a.vertex_count()), 4);
    const std::string bytes = encode(a, profile_options(Profile::predictive));
    StreamingDecoder d("s");
    for (std::size_t at = 0; at < bytes.size() && d.status().playable_frames == 0; at += 64)
        d.feed(std::string_view(bytes).substr(at, 64));
    ASSERT_EQ(d.status().playable_frames, 1u);  // the keyframe packet: only frame 0 is final
    ASSERT_FALSE(d.status().complete);
    const std::vector<Vec3f> k0 = d.frame(0), k16 = d.frame(16), k32 = d.frame(32);
    EXPECT_NE(k0, k16);
    for (std::size_t t : {std::size_t(5), std::size_t(20)}) {
        const std::vector<Vec3f>& left = t < 16 ? k0 : k16;
        const std::vector<Vec3f>& right = t < 16 ? k16 : k32;
        const float w = float(t % 16) / 16.0f;
        const std::vector<Vec3f> frame = d.frame(t);
        ASSERT_EQ(frame.size(), left.size());
        for (std::size_t v = 0; v < frame.size(); ++v)
            ASSERT_EQ(frame[v], (1.0f - w) * left[v] + w * right[v]) << "frame " << t << ", vertex " << v;
    }
}

TEST(StreamingDefault, SmallMeshesGroupMoreFramesPerPacket) {
    // A group (one packet, with its own frequency tables) holds about 2^17 vertex-frames:
    // 16 frames of a large mesh, more of a small one, the whole animation of a tiny one.
    EXPECT_EQ(default_stride_log2(240, 128 * 128), 4);
    EXPECT_EQ(default_stride_log2(240, 64 * 64), 5);
    EXPECT_EQ(default_stride_log2(240, 32 * 32), 7);
    EXPECT_EQ(default_stride_log2(150, 81), 8);     // basicCloth: keyframes 0 and 149 only
    EXPECT_EQ(default_stride_log2(10, 100000), 3);  // short animations as before: stride < T / 2
    EXPECT_EQ(default_stride_log2(1, 1), 0);
    EXPECT_EQ(default_stride_log2(std::size_t(1) << 28, 1), 17);  // within the header's limit of 20
}

INSTANTIATE_TEST_SUITE_P(Profiles, Streaming, ::testing::Values(Profile::paper, Profile::predictive, Profile::cascade),
                         [](const auto& info) { return profile_name(info.param); });

}  // namespace
}  // namespace foldcast::codec
