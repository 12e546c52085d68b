#include <gtest/gtest.h>

#include "foldcast/codec/codec.hpp"
#include "foldcast/core/error.hpp"
#include "test_animations.hpp"

namespace foldcast::codec {
namespace {

EncodeOptions options(Profile p, std::optional<double> max_error = {}, std::optional<double> keep = {}) {
    EncodeOptions o;
    o.profile = p;
    o.max_error_m = max_error;
    o.keep_fraction = keep;
    return o;
}

TEST(Codec, DefaultProfileMeetsItsErrorBoundAndKeepsTopology) {
    const Animation a = test::basic_cloth();
    for (double bound : {1e-2, 1e-3, 1e-4}) {
        const std::string bytes = encode(a, options(Profile::predictive, bound));
        const Animation b = decode(bytes);
        ASSERT_EQ(b.frame_count(), a.frame_count());
        EXPECT_EQ(b.topology.triangles, a.topology.triangles);
        EXPECT_DOUBLE_EQ(b.fps, a.fps);
        const Metrics m = measure(a, b, bytes.size());
        EXPECT_LE(m.max_error_m, bound * (1.0 + 1e-5));
        EXPECT_GT(m.max_error_m, 0.0);
    }
}

TEST(Codec, PaperProfileMeetsMeasuredBoundAndRateFallsWithLooserBound) {
    const Animation a = test::basic_cloth();
    std::size_t previous = 0;
    for (double bound : {1e-4, 1e-3, 1e-2}) {
        const std::string bytes = encode(a, options(Profile::paper, bound));
        const Metrics m = measure(a, decode(bytes), bytes.size());
        EXPECT_LE(m.max_error_m, bound * (1.0 + 1e-5));
        if (previous) {
            EXPECT_LT(bytes.size(), previous);
        }
        previous = bytes.size();
    }
}

TEST(Codec, PaperKeepFractionTradesBitsForError) {
    const Animation a = test::basic_cloth();
    const std::string many = encode(a, options(Profile::paper, {}, 0.5));
    const std::string few = encode(a, options(Profile::paper, {}, 0.05));
    EXPECT_LT(few.size(), many.size());
    EXPECT_GT(measure(a, decode(few), few.size()).kg_error, measure(a, decode(many), many.size()).kg_error);
}

TEST(Codec, UvsAndRegularGridsRoundTrip) {
    const Animation a = test::wave_grid(17, 13, 40);
    for (Profile p : {Profile::predictive, Profile::paper}) {
        const std::string bytes = encode(a, options(p, 1e-4));
        const Animation b = decode(bytes);
        ASSERT_EQ(b.topology.uvs.size(), a.topology.uvs.size());
        EXPECT_EQ(b.topology.uvs[5], a.topology.uvs[5]);
        EXPECT_LE(measure(a, b, bytes.size()).max_error_m, 1e-4 * (1.0 + 1e-5));
    }
}

TEST(Codec, ShortAndSingleFrameAnimations) {
    for (int frames : {1, 2, 3, 12, 13}) {
        const Animation a = test::wave_grid(4, 3, frames);
        for (Profile p : {Profile::predictive, Profile::paper}) {
            const std::string bytes = encode(a, options(p, 1e-4));
            const Animation b = decode(bytes);
            ASSERT_EQ(b.frame_count(), std::size_t(frames));
            EXPECT_LE(measure(a, b, bytes.size()).max_error_m, 1e-4 * (1.0 + 1e-5)) << frames << " frames";
        }
    }
}

TEST(Codec, EncodingIsDeterministic) {
    const Animation a = test::basic_cloth();
    EXPECT_EQ(encode(a, options(Profile::predictive)), encode(a, options(Profile::predictive)));
    EXPECT_EQ(encode(a, options(Profile::paper)), encode(a, options(Profile::paper)));
}

TEST(Codec, BadOptionsAreInputErrors) {
    const Animation a = test::basic_cloth();
    EXPECT_THROW(encode(a, options(Profile::predictive, 1e-3, 0.5)), InputError);
    EXPECT_THROW(encode(a, options(Profile::predictive, {}, 0.5)), InputError);
    EXPECT_THROW(encode(a, options(Profile::paper, -1.0)), InputError);
    EXPECT_THROW(encode(a, options(Profile::paper, {}, 1.5)), InputError);
    EXPECT_THROW(parse_profile("fast"), InputError);
    EXPECT_THROW(encode(Animation{}, options(Profile::paper)), InputError);
}

TEST(Metrics, KarniGotsmanAndRelativeErrors) {
    Animation a = test::wave_grid(5, 5, 4);
    Animation b = a;
    EXPECT_EQ(measure(a, b, 10).kg_error, 0.0);
    for (auto& f : b.frames)
        for (auto& p : f) p.x() += 0.001f;
    const Metrics m = measure(a, b, 100);
    EXPECT_NEAR(m.max_error_m, 0.001, 1e-6);
    EXPECT_NEAR(m.rms_error_rel, m.max_error_rel, 1e-6);
    EXPECT_NEAR(m.bpvf, 800.0 / 100.0, 1e-12);
    EXPECT_GT(m.kg_error, 0.0);
}

}  // namespace
}  // namespace foldcast::codec
