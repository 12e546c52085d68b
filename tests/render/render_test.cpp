// Renders: determinism across thread counts, the white furnace, output files and the CLI.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <fstream>

#include "foldcast/codec/codec.hpp"
#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"
#include "render_fixtures.hpp"
#include "srgb_encode.hpp"
#include "run_command.hpp"

namespace foldcast::render {
namespace {

TEST(Render, ByteIdenticalForAnyThreadCount) {
    const SceneSpec s = test::cloth_scene(70, 45, 3);  // odd sizes: partial tiles and packets
    RenderOptions one, two, three;
    one.threads = 1;
    two.threads = 2;
    three.threads = 3;
    one.aovs = two.aovs = three.aovs = {Aov::albedo, Aov::fold};
    const RenderResult a = render_still(s, one), b = render_still(s, two), c = render_still(s, three);
    ASSERT_EQ(a.beauty.pixels.size(), b.beauty.pixels.size());
    EXPECT_EQ(0, std::memcmp(a.beauty.pixels.data(), b.beauty.pixels.data(), a.beauty.pixels.size() * sizeof(float)));
    EXPECT_EQ(0, std::memcmp(a.beauty.pixels.data(), c.beauty.pixels.data(), a.beauty.pixels.size() * sizeof(float)));
    for (std::size_t i = 0; i < a.aovs.size(); ++i) EXPECT_EQ(a.aovs[i].image.pixels, c.aovs[i].image.pixels);
    EXPECT_EQ(a.stats.rays, c.stats.rays);
    // A different seed gives a different image (the streams really depend on it).
    RenderOptions other = one;
    other.seed = 12345;
    EXPECT_NE(render_still(s, other).beauty.pixels, a.beauty.pixels);
}

TEST(Render, DenoisedAndAdaptiveRendersAreByteIdenticalForAnyThreadCount) {
    const SceneSpec s = test::cloth_scene(45, 29, 32);  // odd sizes: partial tiles and packets
    RenderOptions one, three;
    one.threads = 1;
    three.threads = 3;
    one.denoise = three.denoise = true;
    one.noise_threshold = three.noise_threshold = 0.03;
    const RenderResult a = render_still(s, one), b = render_still(s, three);
    EXPECT_EQ(0, std::memcmp(a.beauty.pixels.data(), b.beauty.pixels.data(), a.beauty.pixels.size() * sizeof(float)));
    EXPECT_EQ(a.stats.mean_spp, b.stats.mean_spp);
    EXPECT_EQ(a.stats.rays, b.stats.rays);
}

TEST(Render, AdaptiveSamplingStopsPixelsByTheirNoise) {
    const SceneSpec s = test::cloth_scene(40, 30, 64);
    RenderOptions o;
    o.threads = 2;
    o.noise_threshold = 1e-6;  // nothing is that clean: every pixel takes all 64
    EXPECT_EQ(render_still(s, o).stats.mean_spp, 64.0);
    o.noise_threshold = 0.9;  // everything is: every pixel stops at the first check, 4
    EXPECT_EQ(render_still(s, o).stats.mean_spp, 4.0);
    o.noise_threshold = 0.02;  // in between: some pixels stop early, some do not
    const RenderResult r = render_still(s, o);
    EXPECT_GT(r.stats.mean_spp, 4.0);
    EXPECT_LT(r.stats.mean_spp, 64.0);
    o.noise_threshold = 0.0;
    EXPECT_EQ(render_still(s, o).stats.mean_spp, 64.0);
}

// The error estimate adaptive sampling stops on is honest: an adaptive render's error
// against a reference, in display units, is about its threshold, neither far above it
// (pixels stopped too early) nor far below (samples wasted).
TEST(Render, AdaptiveSamplingErrorIsAboutItsThreshold) {
    // Up to 256 spp, so that an estimate that over-stated the error could waste many.
    const SceneSpec s = test::cloth_scene(40, 30, 256);
    RenderOptions o;
    o.threads = 2;
    RenderOptions ref_options = o;
    ref_options.spp = 1024;
    const Image ref = render_still(s, ref_options).beauty;
    const auto display_rmse = [&](const Image& img) {
        double sum = 0.0;
        for (std::size_t i = 0; i < img.pixels.size(); ++i)
            if (i % 4 != 3) {
                const double d = (encode_srgb8(img.pixels[i]) - encode_srgb8(ref.pixels[i])) / 255.0;
                sum += d * d;
            }
        return std::sqrt(sum / (0.75 * static_cast<double>(img.pixels.size())));
    };
    constexpr double kThreshold = 0.02;
    o.noise_threshold = kThreshold;
    const RenderResult adaptive = render_still(s, o);
    EXPECT_GT(adaptive.stats.mean_spp, 4.0);
    EXPECT_LT(adaptive.stats.mean_spp, 64.0);
    std::printf("threshold %.3f: mean spp %.1f (garment %.1f, backdrop %.1f), display RMSE %.4f against 1024 spp\n",
                kThreshold, adaptive.stats.mean_spp, adaptive.stats.garment_mean_spp, adaptive.stats.backdrop_mean_spp,
                display_rmse(adaptive.beauty));
    const double error = display_rmse(adaptive.beauty);
    EXPECT_LT(error, 1.5 * kThreshold);
    EXPECT_GT(error, 0.4 * kThreshold) << "the estimate over-states the error: samples are wasted";
}

// With the denoiser, a packet whose pixels it will average together (same normal, depth and
// albedo: the flat backdrop) counts the error of their mean: the backdrop stops at a few
// samples and the folded cloth gets the rest.
TEST(Render, DenoiserAwareAdaptiveSamplingSpendsTheSamplesOnTheCloth) {
    const SceneSpec s = test::cloth_scene(96, 72, 64);
    RenderOptions o;
    o.threads = 2;
    o.noise_threshold = 0.02;
    const RenderResult plain = render_still(s, o);
    o.denoise = true;
    const RenderResult denoised = render_still(s, o);
    std::printf("mean spp garment / backdrop: %.1f / %.1f without the denoiser, %.1f / %.1f with it\n",
                plain.stats.garment_mean_spp, plain.stats.backdrop_mean_spp, denoised.stats.garment_mean_spp,
                denoised.stats.backdrop_mean_spp);
    EXPECT_GT(denoised.stats.garment_mean_spp, 1.3 * denoised.stats.backdrop_mean_spp);
    EXPECT_LT(denoised.stats.backdrop_mean_spp, 0.5 * plain.stats.backdrop_mean_spp);
}

TEST(Render, DenoisingBringsFewSamplesCloserToTheReference) {
    const SceneSpec s = test::cloth_scene(40, 30, 8);
    RenderOptions o;
    o.threads = 2;
    o.denoise = true;
    o.keep_raw = true;
    const RenderResult r = render_still(s, o);
    ASSERT_TRUE(r.raw.has_value());
    RenderOptions ref_options;
    ref_options.threads = 2;
    ref_options.spp = 128;
    const RenderResult ref = render_still(s, ref_options);
    auto rmse = [&](const Image& img) {
        double sum = 0.0;
        for (std::size_t i = 0; i < img.pixels.size(); ++i)
            if (i % 4 != 3) {
                const double d = std::min(1.0f, img.pixels[i]) - std::min(1.0f, ref.beauty.pixels[i]);
                sum += d * d;
            }
        return std::sqrt(sum / static_cast<double>(img.pixels.size()));
    };
    EXPECT_LT(rmse(r.beauty), 0.6 * rmse(*r.raw)) << "denoised " << rmse(r.beauty) << ", raw " << rmse(*r.raw);
    // Without keep_raw nothing extra is kept.
    o.keep_raw = false;
    EXPECT_FALSE(render_still(s, o).raw.has_value());
}

// Embree turns a thread count in its device configuration into a process-wide
// tbb::global_control: that once capped the tracer's own tiles at one thread, silently
// (the images were right, only twice as slow on two cores).  Rendering must leave the
// process's parallelism as it found it.
TEST(Render, LeavesTheProcessParallelismUncapped) {
    using tbb::global_control;
    const std::size_t before = global_control::active_value(global_control::max_allowed_parallelism);
    std::size_t during = 0;  // read while the tracer (and its Embree device) is alive
    RenderOptions two;
    two.threads = 2;
    (void)render_still(test::cloth_scene(16, 12, 1), two, [&](std::string_view, double) {
        during = std::max(during, global_control::active_value(global_control::max_allowed_parallelism));
    });
    ASSERT_GT(during, 0u) << "the progress callback never ran";
    EXPECT_EQ(during, before);
    EXPECT_EQ(global_control::active_value(global_control::max_allowed_parallelism), before);
}

TEST(Render, WhiteFurnaceSphereStaysWithinOnePercent) {
    const auto dir = test::temp_dir();
    SceneSpec s;
    s.garment.source = GarmentSpec::Source::obj;
    s.garment.path = test::write_sphere(dir, 0.5f);
    s.look.appearance.base_colour = Vec3f::Ones();
    s.look.appearance.sheen_colour = Vec3f::Ones();
    s.look.appearance.weave = looks::Weave::none;
    s.look.appearance.roughness = 0.5;
    s.look.appearance.specular = 0.5;
    s.backdrop = SceneSpec::Backdrop::none;
    s.supports = SceneSpec::Supports::none;
    s.studio_preset = false;
    s.environment = Vec3f::Ones();
    s.max_depth = 64;
    s.camera.frame_share = 0.7;
    RenderOptions o;
    o.width = 48;
    o.height = 48;
    o.spp = 64;
    o.aovs = {Aov::depth};
    const RenderResult r = render_still(s, o);
    double sum = 0.0;
    int n = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x)
            if (*r.aovs[0].image.at(x, y) > 0.0f) {  // fully on the sphere
                for (int c = 0; c < 3; ++c) sum += r.beauty.at(x, y)[c];
                n += 3;
            }
    ASSERT_GT(n, 300);
    EXPECT_NEAR(sum / n, 1.0, 0.01);
}

TEST(Render, PngHasTheRequestedSizeAndAlphaWhenTransparent) {
    const auto dir = test::temp_dir();
    SceneSpec s = test::cloth_scene(40, 30, 2);
    s.backdrop = SceneSpec::Backdrop::none;
    s.transparent = true;
    RenderOptions o;
    o.aovs = {Aov::albedo, Aov::normal, Aov::depth, Aov::fold};
    const RenderResult r = render_still(s, o);
    const auto written = write_render(dir / "out.png", r, s);
    EXPECT_EQ(written.size(), 5u);
    const cv::Mat img = cv::imread((dir / "out.png").string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(img.empty());
    EXPECT_EQ(img.cols, 40);
    EXPECT_EQ(img.rows, 30);
    EXPECT_EQ(img.channels(), 4);
    EXPECT_EQ(img.at<cv::Vec4b>(0, 0)[3], 0);      // corner: sky, transparent
    EXPECT_EQ(img.at<cv::Vec4b>(15, 20)[3], 255);  // centre: the garment
    for (const char* aov : {"albedo", "normal", "depth", "fold"}) {
        const cv::Mat a = cv::imread((dir / (std::string("out.") + aov + ".png")).string(), cv::IMREAD_UNCHANGED);
        ASSERT_FALSE(a.empty()) << aov;
        EXPECT_EQ(a.cols, 40) << aov;
    }
    // Opaque scenes give RGB PNGs.
    s.transparent = false;
    write_render(dir / "opaque.png", render_still(s, {}), s);
    EXPECT_EQ(cv::imread((dir / "opaque.png").string(), cv::IMREAD_UNCHANGED).channels(), 3);
}

TEST(Render, ExrIsLinearFloat) {
    const auto dir = test::temp_dir();
    const SceneSpec s = test::cloth_scene(24, 16, 1);
    const RenderResult r = render_still(s, {});
    write_render(dir / "out.exr", r, s);
    const cv::Mat img = cv::imread((dir / "out.exr").string(), cv::IMREAD_UNCHANGED);
    if (img.empty()) GTEST_SKIP() << "this OpenCV cannot read EXR back (writing was done by OpenEXR)";
    EXPECT_EQ(img.cols, 24);
    EXPECT_EQ(img.depth(), CV_32F);
    EXPECT_NEAR(img.at<cv::Vec4f>(8, 12)[2], r.beauty.at(12, 8)[0], 1e-6f);  // BGRA vs RGBA
}

TEST(Render, RejectsUnknownOutputFormat) {
    const SceneSpec s = test::cloth_scene(8, 8, 1);
    EXPECT_THROW(write_render(test::temp_dir() / "out.jpg", render_still(s, {}), s), InputError);
}

TEST(Render, FcaGarmentRendersLikeItsSourceMesh) {
    const auto dir = test::temp_dir();
    SceneSpec obj = test::cloth_scene(32, 24, 2);
    const Mesh mesh = read_obj(obj.garment.path);
    Animation anim;
    anim.topology = mesh.topology;
    anim.frames = {mesh.positions, mesh.positions};
    write_file_atomically(dir / "cloth.fca", codec::encode(anim, {}));
    SceneSpec fca = obj;
    fca.garment.source = GarmentSpec::Source::fca;
    fca.garment.path = dir / "cloth.fca";
    fca.garment.frame = 1;
    const RenderResult a = render_still(obj, {}), b = render_still(fca, {});
    double diff = 0.0;
    for (std::size_t i = 0; i < a.beauty.pixels.size(); ++i) diff += std::abs(a.beauty.pixels[i] - b.beauty.pixels[i]);
    EXPECT_LT(diff / a.beauty.pixels.size(), 0.02);  // lossy codec: nearly the same image
    fca.garment.frame = 2;
    EXPECT_THROW(render_still(fca, {}), InputError);  // names the frame range
}

TEST(RenderCli, JsonReportAndExitStatuses) {
    const auto dir = test::temp_dir();
    std::ofstream(dir / "s.toml") << "[garment]\npath = \"" << test::test_data("animations/basicCloth.obj").string()
                                  << "\"\nscale = 0.1\n[output]\nwidth = 32\nheight = 24\nspp = 2\n";
    const std::string bin = test::foldcast_binary();
    const test::CommandResult ok = test::run_command(bin + " render " + (dir / "s.toml").string() + " -o " +
                                                     (dir / "o.png").string() + " --json --threads 2 2>&1");
    EXPECT_EQ(ok.exit_code, 0) << ok.out;
    for (const char* key :
         {"\"width\":32", "\"height\":24", "\"spp\":2", "\"seconds\"", "\"rays\"", "\"rays_per_second\""})
        EXPECT_NE(ok.out.find(key), std::string::npos) << key << " in " << ok.out;
    EXPECT_TRUE(std::filesystem::exists(dir / "o.png"));
    std::ofstream(dir / "bad.toml") << "[output]\nwidht = 3\n";
    const test::CommandResult bad =
        test::run_command(bin + " render " + (dir / "bad.toml").string() + " -o " + (dir / "b.png").string() + " 2>&1");
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.out.find("bad.toml:2"), std::string::npos) << bad.out;
    EXPECT_FALSE(std::filesystem::exists(dir / "b.png"));
}

}  // namespace
}  // namespace foldcast::render
