// Paths a turntable carries from frame to frame (render/src/path_reuse.hpp): the frames must
// be the same floats as frames traced afresh, and the backdrop's paths must be taken.
#include <gtest/gtest.h>

#include "foldcast/render/studio_setup.hpp"
#include "foldcast/render/tracer.hpp"
#include "render_fixtures.hpp"

namespace foldcast::render {
namespace {

constexpr int kWidth = 48, kHeight = 40;

struct Frames {
    std::vector<RenderResult> results;
};

// Frames 0-3 of a 36-frame turn of the test studio, each traced by its own Tracer as a
// turntable does, with `reuse` (if any) carried from one to the next.
Frames spin(const std::shared_ptr<PathReuse>& reuse, std::uint64_t seed_of_frame_2 = 0) {
    const SceneSpec s = test::cloth_scene(kWidth, kHeight, 8);
    const StudioSetup setup(s, load_garment(s));
    const Camera camera = frame_camera(s.camera, {setup.framing_points(0, 0.0)}, static_cast<double>(kWidth) / kHeight);
    TraceSettings settings = trace_settings(setup.lit_scene(), {});
    settings.noise_threshold = 0.02;
    settings.denoised_later = true;
    settings.keep_features = true;
    settings.reuse = reuse;
    Frames out;
    for (int f = 0; f < 4; ++f) {
        TraceSettings frame = settings;
        if (f == 2 && seed_of_frame_2 != 0) frame.seed = seed_of_frame_2;
        out.results.push_back(Tracer(setup.lit_scene(), setup.geometry(0, -10.0 * f)).render(camera, frame));
    }
    return out;
}

TEST(PathReuse, FramesAreTheSameFloatsAsTracedAfresh) {
    const Frames fresh = spin(nullptr);
    const Frames reused = spin(make_path_reuse());
    for (int f = 0; f < 4; ++f) {
        const RenderResult& a = fresh.results[f];
        const RenderResult& b = reused.results[f];
        EXPECT_EQ(a.beauty.pixels, b.beauty.pixels) << "frame " << f;
        ASSERT_TRUE(a.features && b.features);
        EXPECT_EQ(a.features->variance, b.features->variance) << "frame " << f;
        EXPECT_EQ(a.features->half_a, b.features->half_a) << "frame " << f;
        EXPECT_EQ(a.features->depth, b.features->depth) << "frame " << f;
        EXPECT_EQ(a.stats.mean_spp, b.stats.mean_spp) << "frame " << f;
        EXPECT_EQ(a.stats.reused_paths, 0u);
    }
    // The first frame has nothing to take; the later ones take most of the backdrop's paths
    // (the sheet and clips cover a minority of the image), and trace fewer rays.
    EXPECT_EQ(reused.results[0].stats.reused_paths, 0u);
    for (int f = 1; f < 4; ++f) {
        const double samples = reused.results[f].stats.mean_spp * kWidth * kHeight;
        EXPECT_GT(static_cast<double>(reused.results[f].stats.reused_paths), 0.3 * samples) << "frame " << f;
        EXPECT_LT(reused.results[f].stats.rays, fresh.results[f].stats.rays) << "frame " << f;
    }
}

// The memory budget only limits what is kept: a small one keeps fewer paths and one too
// small for the table of sample slots keeps none, with the same floats either way.
TEST(PathReuse, ABudgetKeepsFewerPathsAndTheSameFloats) {
    const Frames fresh = spin(nullptr);
    const Frames whole = spin(make_path_reuse());
    // The slots of the 48x40 frame's 4 tiles at 8 spp: 4 x 64 x 8 x 16 x 4 bytes = 128 KiB.
    const Frames some = spin(make_path_reuse(std::size_t(1) << 20));
    const Frames none = spin(make_path_reuse(std::size_t(64) << 10));
    for (int f = 1; f < 4; ++f) {
        EXPECT_EQ(some.results[f].beauty.pixels, fresh.results[f].beauty.pixels) << "frame " << f;
        EXPECT_EQ(none.results[f].beauty.pixels, fresh.results[f].beauty.pixels) << "frame " << f;
        EXPECT_GT(some.results[f].stats.reused_paths, 0u) << "frame " << f;
        EXPECT_LT(some.results[f].stats.reused_paths, whole.results[f].stats.reused_paths) << "frame " << f;
        EXPECT_EQ(none.results[f].stats.reused_paths, 0u) << "frame " << f;
    }
}

TEST(PathReuse, AnotherSeedTakesNothing) {
    const Frames reused = spin(make_path_reuse(), 12345);
    EXPECT_GT(reused.results[1].stats.reused_paths, 0u);
    EXPECT_EQ(reused.results[2].stats.reused_paths, 0u);  // its seed differs from frame 1's
    EXPECT_EQ(reused.results[3].stats.reused_paths, 0u);  // frame 2 kept for its own seed
}

}  // namespace
}  // namespace foldcast::render
