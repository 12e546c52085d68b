// Path-traced noise measurements against high-spp references: the rod's split and the
// denoised still's mixed pixels.  Labelled `slow` (seconds here, about a minute each under
// the sanitizers): they run in CI's Release stage, not again in its sanitizer stage.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "render_fixtures.hpp"

namespace foldcast::render {
namespace {

// The rod's highlight at 16 spp: its first hit takes four BSDF directions for the light its
// lobe reflects (PathIntegrator), which halves the rod's noise against one direction (measured
// here, seeds 1-3: the squared error of its linear values 0.051 with one, 0.027 with four) and
// keeps its mean (16 spp's is 7-9 % below 512 spp's with one direction or four alike: the
// highlight's rare bright samples).
TEST(Render, TheRodsHighlightIsLessNoisyPerSample) {
    SceneSpec s = test::cloth_scene(96, 72, 16);
    s.supports = SceneSpec::Supports::rod;
    s.backdrop_colour = Vec3f(0.85f, 0.84f, 0.82f);  // as the gallery's: not grey, unlike the metal
    RenderOptions o;
    o.threads = 2;
    o.aovs = {Aov::albedo};
    RenderOptions ref_options = o;
    ref_options.spp = 512;
    ref_options.seed = 7919;
    const RenderResult ref = render_still(s, ref_options);
    // The rod's pixels: the metal's albedo is grey (the garment's is not, nor the backdrop's).
    const Image& albedo = ref.aovs[0].image;
    double error = 0.0, sum = 0.0, ref_sum = 0.0;
    int n = 0;
    for (const std::uint64_t seed : {1ull, 2ull, 3ull}) {
        o.seed = seed;
        const RenderResult r = render_still(s, o);
        for (int y = 0; y < 72; ++y)
            for (int x = 0; x < 96; ++x) {
                const float* a = albedo.at(x, y);
                if (!(a[0] > 0.0f && a[0] == a[1] && a[1] == a[2])) continue;
                for (int c = 0; c < 3; ++c) {
                    const double d = r.beauty.at(x, y)[c] - ref.beauty.at(x, y)[c];
                    error += d * d;
                    sum += r.beauty.at(x, y)[c];
                    ref_sum += ref.beauty.at(x, y)[c];
                }
                n += 3;
            }
    }
    ASSERT_GT(n, 3 * 3 * 40) << "the rod is not in the picture";
    EXPECT_LT(error / n, 0.038) << "the rod's squared error at 16 spp";
    EXPECT_NEAR(sum / ref_sum, 1.0, 0.15) << "the rod's mean";
}

// A denoised still's mixed pixels (two surfaces in one pixel: the cloth's and the rod's
// silhouettes) and the rod's metal take 4 x spp samples (tracer.cpp, kMixedSppFactor): at
// 16 spp + denoise their squared error against 512 spp, seeds 1-3, was 0.00106 with 16 samples
// and 0.00021 with 64 (linear values, measured when written).
TEST(Render, MixedPixelsOfADenoisedStillTakeMoreSamples) {
    SceneSpec s = test::cloth_scene(96, 72, 16);
    s.supports = SceneSpec::Supports::rod;
    s.backdrop_colour = Vec3f(0.85f, 0.84f, 0.82f);
    RenderOptions o;
    o.threads = 2;
    o.denoise = true;
    RenderOptions ref_options = o;
    ref_options.denoise = false;
    ref_options.spp = 512;
    ref_options.seed = 7919;
    ref_options.aovs = {Aov::albedo};
    const RenderResult ref = render_still(s, ref_options);
    // Mixed pixels: the reference's albedo differs from a 4-neighbour's (a silhouette), or is
    // the metal's grey (the rod, whose highlight is thin).
    const Image& albedo = ref.aovs[0].image;
    const auto grey = [&](int x, int y) {
        const float* a = albedo.at(x, y);
        return a[0] > 0.0f && a[0] == a[1] && a[1] == a[2];
    };
    std::vector<bool> mixed(96 * 72, false);
    int mixed_count = 0;
    for (int y = 1; y + 1 < 72; ++y)
        for (int x = 1; x + 1 < 96; ++x) {
            float step = 0.0f;
            for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}})
                for (int c = 0; c < 3; ++c)
                    step = std::max(step, std::abs(albedo.at(x, y)[c] - albedo.at(x + dx, y + dy)[c]));
            mixed[y * 96 + x] = step > 0.1f || grey(x, y);
            mixed_count += mixed[y * 96 + x];
        }
    ASSERT_GT(mixed_count, 150) << "the silhouettes and the rod are not in the picture";
    double error = 0.0;
    int n = 0;
    for (const std::uint64_t seed : {1ull, 2ull, 3ull}) {
        o.seed = seed;
        const RenderResult r = render_still(s, o);
        EXPECT_GT(r.stats.mean_spp, 16.5) << "no pixel took more samples";
        EXPECT_LT(r.stats.mean_spp, 32.0) << "too many pixels took more samples";
        for (int i = 0; i < 96 * 72; ++i) {
            if (!mixed[i]) continue;
            for (int c = 0; c < 3; ++c) {
                const double d = r.beauty.pixels[4 * i + c] - ref.beauty.pixels[4 * i + c];
                error += d * d;
            }
            n += 3;
        }
    }
    RecordProperty("mixed_error", std::to_string(error / n));
    EXPECT_LT(error / n, 0.0005) << "the mixed pixels' squared error at 16 spp + denoise";
    // A plain render takes spp samples in every pixel.
    o.denoise = false;
    EXPECT_EQ(render_still(s, o).stats.mean_spp, 16.0);
}

}  // namespace
}  // namespace foldcast::render
