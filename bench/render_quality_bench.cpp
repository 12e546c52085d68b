// bench_render_quality: what the denoiser and the sampler buy, against high-spp references
// (docs/benchmarks.md, "render: image quality").  Prints
//   rmse:    the default scene at 320x180, plain and --denoise at several spp, RMSE of the
//            sRGB-encoded RGB against a --ref-spp reference;
//   twill:   a 5 cm close-up of denim's 3/1 twill (bench/scenes/twill_closeup.toml), SSIM
//            of the luma and RMSE against the reference for plain 256 spp and 16 spp + denoise;
//   flicker: frames 0-7 of the default scene's 36-frame turntable at 96x96 (--size N: NxN): RMSE against
//            reference frames, and flicker = RMS over pixels and frame pairs of the change
//            from frame to frame minus the reference's change (0 = the noise does not move),
//            without and with the temporal filter; a second reference (another seed) measures
//            the reference's own share, and "own" is each row's flicker without it;
//   flicker-samples: the same measure for denoised frames at 16, 32, 64 and 128 spp, with
//            --noise-threshold 0.02 and without it: what less flicker costs (not in `all`);
//   adaptive: the default scene at 640x360 with --noise-threshold, plain and denoised: time,
//            mean spp, where the samples went (garment vs backdrop) and RMSE;
//   looks:   every shipped look in the default scene at 320x180, 16 spp + denoise against
//            plain 256 spp, each against the look's own reference: a look whose colour or
//            gloss the denoiser mishandles shows as a denoised error far above plain 256 spp's.
// References are rendered once and kept in --out.  Timed figures are wall clock on whatever
// load the machine has; never asserts anything.
//   bench_render_quality [rmse|twill|flicker|flicker-samples|adaptive|looks|all]
//                        [--out DIR] [--threads N] [--ref-spp N] [--size N]
#include <OpenEXR/ImfArray.h>
#include <OpenEXR/ImfRgbaFile.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "foldcast/compare/diff.hpp"
#include "foldcast/core/colour.hpp"
#include "foldcast/batch/turntable.hpp"
#include "foldcast/render/render.hpp"

using namespace foldcast;
namespace fs = std::filesystem;

namespace {

struct Args {
    std::string part = "all";
    fs::path out = fs::path(FOLDCAST_BINARY_DIR) / "bench-quality";  // references kept in the build tree
    int threads = 2;
    int ref_spp = 2048;
    int flicker_size = 96;  // the flicker part's frame side in pixels
};

std::string source(const std::string& relative) { return std::string(FOLDCAST_SOURCE_DIR) + "/" + relative; }

// sRGB-encoded RGB in [0,1], as the PNG shows it.
compare::Image display(const render::Image& linear) {
    compare::Image out(linear.width, linear.height, 3);
    for (int y = 0; y < linear.height; ++y)
        for (int x = 0; x < linear.width; ++x)
            for (int c = 0; c < 3; ++c)
                out.at(x, y, c) = std::clamp(linear_to_srgb(std::max(0.0f, linear.at(x, y)[c])), 0.0f, 1.0f);
    return out;
}

compare::Image luma(const compare::Image& rgb) {
    compare::Image out(rgb.width, rgb.height, 1);
    for (int y = 0; y < rgb.height; ++y)
        for (int x = 0; x < rgb.width; ++x)
            out.at(x, y, 0) = 0.2126f * rgb.at(x, y, 0) + 0.7152f * rgb.at(x, y, 1) + 0.0722f * rgb.at(x, y, 2);
    return out;
}

double rmse(const compare::Image& a, const compare::Image& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.values.size(); ++i)
        sum += (a.values[i] - b.values[i]) * double(a.values[i] - b.values[i]);
    return std::sqrt(sum / static_cast<double>(a.values.size()));
}

struct Rendered {
    render::RenderResult result;
    double seconds = 0.0;
};

Rendered render(const render::SceneSpec& scene, int w, int h, int spp, bool denoise, const Args& args,
                double threshold = 0.0, std::vector<render::Aov> aovs = {},
                std::optional<std::uint64_t> seed = std::nullopt) {
    render::RenderOptions o;
    o.seed = seed;
    o.width = w;
    o.height = h;
    o.spp = spp;
    o.threads = args.threads;
    o.denoise = denoise;
    o.noise_threshold = threshold;
    o.aovs = std::move(aovs);
    const auto t0 = std::chrono::steady_clock::now();
    Rendered r{render::render_still(scene, o), 0.0};
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

// The reference's display image, kept as raw floats in --out so that reruns skip it (or
// taken from NAME_refSPP_seed7919.exr there, e.g. bench_cycles' foldcast reference).  Rendered
// with its own seed: with the scene's, a test image of N spp would be the reference's first N
// samples, correlated with it, and its error understated the more the closer N is to the
// reference's count (plain 256 spp against 1024 shared a quarter of them).
constexpr std::uint64_t kReferenceSeed = 7919;
compare::Image reference(const std::string& name, const render::SceneSpec& scene, int w, int h, const Args& args) {
    const std::string stem = name + "_ref" + std::to_string(args.ref_spp) + "_seed" + std::to_string(kReferenceSeed);
    const fs::path file = args.out / (stem + ".f32");
    const fs::path exr = args.out / (stem + ".exr");
    compare::Image img(w, h, 3);
    if (fs::exists(exr)) {
        Imf::RgbaInputFile in(exr.c_str());
        Imf::Array2D<Imf::Rgba> px(h, w);
        in.setFrameBuffer(&px[0][0], 1, w);
        in.readPixels(0, h - 1);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float rgb[3] = {px[y][x].r, px[y][x].g, px[y][x].b};
                for (int c = 0; c < 3; ++c)
                    img.at(x, y, c) = std::clamp(linear_to_srgb(std::max(0.0f, rgb[c])), 0.0f, 1.0f);
            }
        return img;
    }
    if (FILE* f = std::fopen(file.c_str(), "rb")) {
        const std::size_t n = std::fread(img.values.data(), sizeof(float), img.values.size(), f);
        std::fclose(f);
        if (n == img.values.size()) return img;
    }
    const Rendered r = render(scene, w, h, args.ref_spp, false, args, 0.0, {}, kReferenceSeed);
    std::printf("  (%s reference, %d spp, seed %llu: %.1f s)\n", name.c_str(), args.ref_spp,
                static_cast<unsigned long long>(kReferenceSeed), r.seconds);
    img = display(r.result.beauty);
    FILE* f = std::fopen(file.c_str(), "wb");
    std::fwrite(img.values.data(), sizeof(float), img.values.size(), f);
    std::fclose(f);
    return img;
}

void part_rmse(const Args& args) {
    const render::SceneSpec scene = render::load_scene(source("gallery/default.toml"));
    const compare::Image ref = reference("default_320x180", scene, 320, 180, args);
    std::printf("default scene 320x180, RMSE (sRGB) against %d spp\n%6s %10s %8s %10s %8s\n", args.ref_spp, "spp",
                "plain s", "RMSE", "denoise s", "RMSE");
    for (const int spp : {4, 16, 64, 256}) {
        const Rendered p = render(scene, 320, 180, spp, false, args);
        const Rendered d = render(scene, 320, 180, spp, true, args);
        std::printf("%6d %10.2f %8.4f %10.2f %8.4f\n", spp, p.seconds, rmse(ref, display(p.result.beauty)), d.seconds,
                    rmse(ref, display(d.result.beauty)));
        std::fflush(stdout);
    }
}

void part_twill(const Args& args) {
    const render::SceneSpec scene = render::load_scene(source("bench/scenes/twill_closeup.toml"));
    const compare::Image ref = reference("twill_192", scene, 192, 192, args);
    const compare::Image ref_luma = luma(ref);
    std::printf("twill close-up 192x192 against %d spp\n%-22s %8s %8s %8s\n", args.ref_spp, "image", "seconds", "SSIM",
                "RMSE");
    struct Row {
        const char* name;
        int spp;
        bool denoise;
    };
    for (const Row row :
         {Row{"plain 16 spp", 16, false}, Row{"plain 64 spp", 64, false}, Row{"plain 256 spp", 256, false},
          Row{"16 spp + denoise", 16, true}, Row{"64 spp + denoise", 64, true}}) {
        const Rendered r = render(scene, 192, 192, row.spp, row.denoise, args);
        const compare::Image img = display(r.result.beauty);
        std::printf("%-22s %8.2f %8.4f %8.4f\n", row.name, r.seconds, compare::ssim_luma(ref_luma, luma(img)),
                    rmse(ref, img));
        std::fflush(stdout);
    }
}

// Turntable frames kFlickerFirst..kFlickerLast-1 of 36 at the flicker parts' size.
constexpr int kFlickerFirst = 0, kFlickerLast = 8;
// Bands of image rows the flicker is also split by, in rows of a 320-row frame (scaled to the
// frame's size): in the default scene rows 40-80 hold the rod, the clips and the wires' lower
// ends, rows 120-200 the cloth's middle.
constexpr std::array<std::pair<int, int>, 5> kFlickerBands = {{{0, 40}, {40, 80}, {80, 120}, {120, 200}, {200, 320}}};

// One way of rendering the turntable's frames.  A name starting with "ref" is a reference:
// rendered once and kept in --out.
struct TurntableRow {
    std::string name;
    int spp;
    bool denoise = false, temporal = false;
    double threshold = 0.0;
    std::optional<std::uint64_t> seed = std::nullopt;
};
struct TurntableRun {
    std::vector<compare::Image> frames;
    double seconds = 0.0;  // 0 for a reference found in --out
};
TurntableRun flicker_frames(const Args& args, const render::SceneSpec& scene, const TurntableRow& row) {
    const int size = args.flicker_size;
    // The default size keeps the names of earlier runs' references.  (Built with append: GCC 12
    // takes `"_" + std::to_string(size)` here for an overlapping memcpy, -Wrestrict.)
    std::string dir_name = "turntable_" + row.name;
    if (size != 96) dir_name.append("_").append(std::to_string(size));
    const fs::path dir = args.out / dir_name;
    bool cached = true;
    for (int f = kFlickerFirst; f < kFlickerLast; ++f)
        cached = cached && fs::exists(batch::turntable_frame_path(dir, f));
    TurntableRun run;
    if (!cached || row.name.rfind("ref", 0) != 0) {
        batch::TurntableOptions o;
        o.render.width = o.render.height = size;
        o.render.spp = row.spp;
        o.render.threads = args.threads;
        o.render.denoise = row.denoise;
        o.render.noise_threshold = row.threshold;
        o.render.seed = row.seed;
        o.temporal = row.temporal;
        o.total_frames = 36;
        o.first_frame = kFlickerFirst;
        o.last_frame = kFlickerLast;
        run.seconds = batch::render_turntable(scene, dir.string() + "/", o).stats.seconds;
    }
    for (int f = kFlickerFirst; f < kFlickerLast; ++f)
        run.frames.push_back(compare::read_image(batch::turntable_frame_path(dir, f)));
    return run;
}

// Flicker (RMS over pixels and frame pairs of the change from frame to frame minus the
// reference's change), whole, split into edge pixels and the rest, and by kFlickerBands.
struct Flicker {
    double whole = 0.0, interior = 0.0, edges = 0.0;
    std::array<double, kFlickerBands.size()> bands{};
};

// The flicker parts' reference frames, their edge pixels, and what the reference's own noise
// adds to a row's flicker.  Two references with their own samples, seeds 7 and 8 (one sharing
// the test's would understate both figures: a 16-spp test is the first 16 of its samples):
// their flicker against each other is twice the square of what one reference's own noise adds
// to every row's figure, so each row's own flicker is measured, not extrapolated.
struct FlickerReference {
    std::vector<compare::Image> frames;
    // Per frame pair, per pixel: the reference differs from a 4-neighbour by more than 0.08 in
    // either frame (silhouettes, the rod, the wires), where what flickers is more than the
    // noise of shading.
    std::vector<std::vector<bool>> edge;
    double edge_share = 0.0;
    Flicker between;  // the two references against each other

    Flicker flicker(const std::vector<compare::Image>& test) const {
        const int w = frames[0].width, h = frames[0].height;
        double sum = 0.0, edge_sum = 0.0;
        std::size_t n = 0, edge_n = 0;
        std::vector<double> row_sums(h, 0.0);
        for (std::size_t f = 0; f + 1 < test.size(); ++f)
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const bool is_edge = edge[f][static_cast<std::size_t>(y) * w + x];
                    for (int c = 0; c < 3; ++c) {
                        const double d = (test[f + 1].at(x, y, c) - test[f].at(x, y, c)) -
                                         (frames[f + 1].at(x, y, c) - frames[f].at(x, y, c));
                        (is_edge ? edge_sum : sum) += d * d;
                        ++(is_edge ? edge_n : n);
                        row_sums[y] += d * d;
                    }
                }
        Flicker out;
        out.interior = std::sqrt(sum / static_cast<double>(std::max<std::size_t>(1, n)));
        out.edges = std::sqrt(edge_sum / static_cast<double>(std::max<std::size_t>(1, edge_n)));
        out.whole = std::sqrt((sum + edge_sum) / static_cast<double>(n + edge_n));
        const double per_row = 3.0 * w * static_cast<double>(test.size() - 1);
        for (std::size_t b = 0; b < kFlickerBands.size(); ++b) {
            const int y0 = kFlickerBands[b].first * h / 320, y1 = kFlickerBands[b].second * h / 320;
            double band = 0.0;
            for (int y = y0; y < y1; ++y) band += row_sums[y];
            out.bands[b] = std::sqrt(band / (per_row * std::max(1, y1 - y0)));
        }
        return out;
    }
    // A row's flicker with the reference's own share taken out.
    Flicker own(const Flicker& measured) const {
        const auto take_out = [](double m, double pair) { return std::sqrt(std::max(0.0, m * m - 0.5 * pair * pair)); };
        Flicker out;
        out.whole = take_out(measured.whole, between.whole);
        out.interior = take_out(measured.interior, between.interior);
        out.edges = take_out(measured.edges, between.edges);
        for (std::size_t b = 0; b < out.bands.size(); ++b) out.bands[b] = take_out(measured.bands[b], between.bands[b]);
        return out;
    }
};

FlickerReference flicker_reference(const Args& args, const render::SceneSpec& scene) {
    const std::string name = "ref" + std::to_string(args.ref_spp) + "_seed";
    FlickerReference r;
    r.frames = flicker_frames(args, scene, {name + "7", args.ref_spp, false, false, 0.0, 7}).frames;
    const int w = r.frames[0].width, h = r.frames[0].height;
    std::size_t edges = 0;
    for (std::size_t f = 0; f + 1 < r.frames.size(); ++f) {
        std::vector<bool>& edge = r.edge.emplace_back(static_cast<std::size_t>(w) * h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                float contrast = 0.0f;
                for (const compare::Image* frame : {&r.frames[f], &r.frames[f + 1]})
                    for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
                        const int qx = x + dx, qy = y + dy;
                        if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
                        for (int c = 0; c < 3; ++c)
                            contrast = std::max(contrast, std::abs(frame->at(x, y, c) - frame->at(qx, qy, c)));
                    }
                edge[static_cast<std::size_t>(y) * w + x] = contrast > 0.08f;
                edges += contrast > 0.08f ? 1 : 0;
            }
    }
    r.edge_share = static_cast<double>(edges) / static_cast<double>(r.edge.size() * w * h);
    r.between = r.flicker(flicker_frames(args, scene, {name + "8", args.ref_spp, false, false, 0.0, 8}).frames);
    const int size = args.flicker_size;
    std::printf("turntable frames %d-%d of 36 at %dx%d against %d spp frames; edge pixels %.1f %%\n", kFlickerFirst,
                kFlickerLast - 1, size, size, args.ref_spp, 100.0 * r.edge_share);
    std::printf(
        "the reference's own flicker (whole / interior / edges): %.4f / %.4f / %.4f; \"own\": a row's flicker "
        "with it taken out; the last columns: own flicker by rows of a 320-row frame\n",
        r.between.whole / std::sqrt(2.0), r.between.interior / std::sqrt(2.0), r.between.edges / std::sqrt(2.0));
    std::printf("%-24s %8s %8s %8s %8s %8s %8s %8s %8s", "frames", "seconds", "RMSE", "flicker", "interior", "edges",
                "own", "own int", "own edge");
    for (const auto& [y0, y1] : kFlickerBands)
        std::printf(" %9s", (std::to_string(y0) + "-" + std::to_string(y1)).c_str());
    std::printf("\n%-24s %8s %8s %8s %8s %8s %8s %8s %8s", "reference's own", "", "", "", "", "", "", "", "");
    for (const double band : r.between.bands) std::printf(" %9.4f", band / std::sqrt(2.0));
    std::printf("\n");
    return r;
}

void print_flicker_row(const Args& args, const render::SceneSpec& scene, const TurntableRow& row,
                       const FlickerReference& ref) {
    const TurntableRun run = flicker_frames(args, scene, row);
    double err = 0.0;
    for (std::size_t f = 0; f < run.frames.size(); ++f) err += rmse(ref.frames[f], run.frames[f]) / run.frames.size();
    const Flicker fl = ref.flicker(run.frames);
    const Flicker own = ref.own(fl);
    std::printf("%-24s %8.2f %8.4f %8.4f %8.4f %8.4f %8.4f %8.4f %8.4f", row.name.c_str(), run.seconds, err, fl.whole,
                fl.interior, fl.edges, own.whole, own.interior, own.edges);
    for (const double band : own.bands) std::printf(" %9.4f", band);
    std::printf("\n");
    std::fflush(stdout);
}

void part_flicker(const Args& args) {
    const render::SceneSpec scene = render::load_scene(source("gallery/default.toml"));
    const FlickerReference ref = flicker_reference(args, scene);
    // denoise_16_t02 is the README's turntable: adaptive sampling at --noise-threshold 0.02.
    for (const TurntableRow& row :
         {TurntableRow{"plain_16", 16}, TurntableRow{"plain_64", 64}, TurntableRow{"denoise_4", 4, true},
          TurntableRow{"denoise_8", 8, true}, TurntableRow{"denoise_16", 16, true},
          TurntableRow{"denoise_16_t02", 16, true, false, 0.02}, TurntableRow{"temporal_4", 4, true, true},
          TurntableRow{"temporal_8", 8, true, true}, TurntableRow{"temporal_16", 16, true, true}})
        print_flicker_row(args, scene, row, ref);
}

// What less flicker costs: denoised turntable frames at 16-128 spp, with the README's
// --noise-threshold 0.02 and without adaptive sampling.
void part_flicker_samples(const Args& args) {
    const render::SceneSpec scene = render::load_scene(source("gallery/default.toml"));
    const FlickerReference ref = flicker_reference(args, scene);
    for (const double threshold : {0.02, 0.0})
        for (const int spp : {16, 32, 64, 128}) {
            const std::string name = "denoise_" + std::to_string(spp) + (threshold > 0.0 ? "_t02" : "_t0");
            print_flicker_row(args, scene, {"samples_" + name, spp, true, false, threshold}, ref);
        }
}

void part_adaptive(const Args& args) {
    const render::SceneSpec scene = render::load_scene(source("gallery/default.toml"));
    constexpr int kWidth = 640, kHeight = 360;
    const compare::Image ref = reference("default_640x360", scene, kWidth, kHeight, args);
    std::printf("adaptive sampling, default scene %dx%d, against %d spp\n%-30s %8s %8s %8s %8s %8s\n", kWidth, kHeight,
                args.ref_spp, "render", "seconds", "mean spp", "garment", "backdrop", "RMSE");
    struct Row {
        const char* name;
        int spp;
        bool denoise;
        double threshold;
    };
    for (const Row row : {Row{"plain 64 spp", 64, false, 0.0}, Row{"256 spp, threshold 0.01", 256, false, 0.01},
                          Row{"256 spp, threshold 0.02", 256, false, 0.02}, Row{"4 spp + denoise", 4, true, 0.0},
                          Row{"8 spp + denoise", 8, true, 0.0}, Row{"16 spp + denoise", 16, true, 0.0},
                          Row{"16 spp + denoise, 0.01", 16, true, 0.01}, Row{"16 spp + denoise, 0.02", 16, true, 0.02},
                          Row{"16 spp + denoise, 0.04", 16, true, 0.04}}) {
        const Rendered r = render(scene, kWidth, kHeight, row.spp, row.denoise, args, row.threshold);
        const render::RenderStats& s = r.result.stats;
        std::printf("%-30s %8.2f %8.2f %8.2f %8.2f %8.4f\n", row.name, r.seconds, s.mean_spp, s.garment_mean_spp,
                    s.backdrop_mean_spp, rmse(ref, display(r.result.beauty)));
        std::fflush(stdout);
    }
}

// Velvet's contour lines (2026-11-26: its green albedo crossed the demodulation floor, where
// the divisor jumped) were found only by looking at every look's swatch against a
// high-spp one; this part measures that for each look.
void part_looks(const Args& args) {
    const render::SceneSpec base = render::load_scene(source("gallery/default.toml"));
    const looks::Library library = looks::Library::load_default();
    constexpr int kW = 320, kH = 180;
    std::printf("every look in the default scene at %dx%d, RMSE (sRGB) against %d spp\n%-20s %10s %10s %10s %6s\n", kW,
                kH, args.ref_spp, "look", "plain 16", "16 + dn", "plain 256", "ratio");
    for (const std::string& name : library.names()) {
        render::SceneSpec scene = base;
        scene.look = library.get(name);
        const compare::Image ref =
            reference("look_" + name + "_" + std::to_string(kW) + "x" + std::to_string(kH), scene, kW, kH, args);
        const double plain16 = rmse(ref, display(render(scene, kW, kH, 16, false, args).result.beauty));
        const double denoised = rmse(ref, display(render(scene, kW, kH, 16, true, args).result.beauty));
        const double plain256 = rmse(ref, display(render(scene, kW, kH, 256, false, args).result.beauty));
        std::printf("%-20s %10.4f %10.4f %10.4f %6.2f\n", name.c_str(), plain16, denoised, plain256,
                    denoised / plain256);
        std::fflush(stdout);
    }
}

}  // namespace

int main(int argc, char** argv) {
    Args args;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--out" && i + 1 < argc)
            args.out = argv[++i];
        else if (a == "--threads" && i + 1 < argc)
            args.threads = std::stoi(argv[++i]);
        else if (a == "--ref-spp" && i + 1 < argc)
            args.ref_spp = std::stoi(argv[++i]);
        else if (a == "--size" && i + 1 < argc)
            args.flicker_size = std::stoi(argv[++i]);
        else
            args.part = a;
    }
    struct Part {
        const char* name;
        void (*run)(const Args&);
        bool in_all;
    };
    const Part parts[] = {{"rmse", part_rmse, true},         {"twill", part_twill, true},
                          {"flicker", part_flicker, true},   {"flicker-samples", part_flicker_samples, false},
                          {"adaptive", part_adaptive, true}, {"looks", part_looks, true}};
    const bool all = args.part == "all";
    if (!all && std::none_of(std::begin(parts), std::end(parts), [&](const Part& p) { return args.part == p.name; })) {
        std::string names;
        for (const Part& p : parts) names.append(p.name).append(", ");
        std::fprintf(stderr, "bench_render_quality: no part '%s' (%sor all)\n", args.part.c_str(), names.c_str());
        return 2;
    }
    fs::create_directories(args.out);
    for (const Part& p : parts)
        if (all ? p.in_all : args.part == p.name) p.run(args);
    return 0;
}
