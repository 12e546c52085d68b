// bench_cycles: foldcast against Blender's Cycles on the same scene (docs/benchmarks.md,
// "foldcast vs Cycles").  Run by hand; needs `blender` (Debian's) on PATH.
//
// Exports the scene (bench_cycles_export's JSON, written by this program too), renders a
// high-spp reference with each renderer, then each renderer at every --spp, and prints per
// renderer and spp: wall-clock and CPU seconds and RMSE against its OWN reference (sRGB-encoded
// RGB in [0,1], rendered with another seed than the tests); then the time each needs to reach
// the same RMSE (log-log interpolation between measured spp) and the ratio, by wall clock and
// by CPU.  foldcast is also measured with --denoise.  Both use --threads; neither's seconds
// include the drape (foldcast drapes once before, Cycles is handed the mesh).
//   bench_cycles [SCENE.toml] [--width 320] [--height 180] [--spp 4,16,64,256]
//                [--ref-spp 2048] [--threads 2] [--out bench-cycles/]
// References are kept in --out and reused when present (delete them to re-render).
//   bench_cycles --rmse REF.exr TEST.exr...   prints the RMSE of each TEST against REF.
#include <OpenEXR/ImfRgbaFile.h>
#include <OpenEXR/ImfArray.h>

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "foldcast/core/colour.hpp"
#include "foldcast/render/render.hpp"

using namespace foldcast;
using namespace foldcast::render;
namespace fs = std::filesystem;

namespace {

struct Args {
    std::string scene = std::string(FOLDCAST_SOURCE_DIR) + "/gallery/default.toml";
    int width = 320, height = 180, ref_spp = 2048, threads = 2;
    std::vector<int> spp = {4, 16, 64, 256};
    fs::path out = "bench-cycles";
};

std::vector<float> read_exr_srgb(const fs::path& path, int* w, int* h) {
    Imf::RgbaInputFile file(path.c_str());
    const Imath::Box2i dw = file.dataWindow();
    *w = dw.max.x - dw.min.x + 1;
    *h = dw.max.y - dw.min.y + 1;
    Imf::Array2D<Imf::Rgba> px(*h, *w);
    file.setFrameBuffer(&px[0][0] - dw.min.x - dw.min.y * *w, 1, *w);
    file.readPixels(dw.min.y, dw.max.y);
    std::vector<float> out;
    out.reserve(static_cast<std::size_t>(*w) * *h * 3);
    for (int y = 0; y < *h; ++y)
        for (int x = 0; x < *w; ++x)
            for (const float v : {float(px[y][x].r), float(px[y][x].g), float(px[y][x].b)})
                out.push_back(std::clamp(linear_to_srgb(std::max(0.0f, v)), 0.0f, 1.0f));
    return out;
}

double rmse(const fs::path& ref, const fs::path& test) {
    int w0, h0, w1, h1;
    const std::vector<float> a = read_exr_srgb(ref, &w0, &h0), b = read_exr_srgb(test, &w1, &h1);
    if (w0 != w1 || h0 != h1) throw std::runtime_error("size mismatch: " + ref.string() + " vs " + test.string());
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * static_cast<double>(a[i] - b[i]);
    return std::sqrt(sum / a.size());
}

// The references use another seed than the tested renders: a reference that shares the test's
// first samples is correlated with it and understates its error, the more so at high spp.
constexpr int kTestSeed = 1, kReferenceSeed = 7919;

// Wall-clock and CPU seconds (all threads): on a shared machine the wall clock carries the
// other jobs' load, the CPU time much less of it.
struct Seconds {
    double wall = 0.0, cpu = 0.0;
};

double process_cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

Seconds render_cycles(const Args& args, const fs::path& json, const fs::path& exr, int spp, int seed) {
    const fs::path log = exr.string() + ".log";
    const std::string cmd = "blender -b --factory-startup -P " + std::string(FOLDCAST_SOURCE_DIR) +
                            "/bench/cycles/render_cycles.py -- " + json.string() + " " + exr.string() + " " +
                            std::to_string(spp) + " " + std::to_string(args.threads) + " " + std::to_string(seed) +
                            " > " + log.string() + " 2>&1";
    if (std::system(cmd.c_str()) != 0) throw std::runtime_error("blender failed: see " + log.string());
    std::ifstream in(log);
    std::string line;
    Seconds t{-1.0, -1.0};
    while (std::getline(in, line)) {
        if (line.rfind("CYCLES_SECONDS ", 0) == 0) t.wall = std::stod(line.substr(15));
        if (line.rfind("CYCLES_CPU_SECONDS ", 0) == 0) t.cpu = std::stod(line.substr(19));
    }
    if (t.wall < 0.0 || t.cpu < 0.0)
        throw std::runtime_error("no CYCLES_SECONDS / CYCLES_CPU_SECONDS in " + log.string());
    return t;
}

// foldcast on the garment draped once beforehand (load_garment): Cycles is handed the finished
// mesh too, so neither renderer's seconds include the drape.  They include what Cycles'
// include: the studio's meshes, the BVH build and the render.
Seconds render_foldcast(const Args& args, const SceneSpec& scene, const GarmentData& garment, const fs::path& exr,
                        int spp, bool denoise, int seed) {
    RenderOptions o;
    o.seed = std::uint64_t(seed);
    o.width = args.width;
    o.height = args.height;
    o.spp = spp;
    o.threads = args.threads;
    o.denoise = denoise;
    const auto t0 = std::chrono::steady_clock::now();
    const double cpu0 = process_cpu_seconds();
    const RenderResult r = render_still(scene, garment, o);
    const Seconds t{std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                    process_cpu_seconds() - cpu0};
    write_render(exr, r, scene);
    return t;
}

struct Point {
    int spp;
    Seconds time;
    double rmse;
};

// Seconds to reach `target` RMSE: log-log interpolation between the measured points (and
// extrapolation at the ends with the Monte Carlo slope, RMSE ~ time^-1/2).
double time_for(const std::vector<Point>& pts, double target, double Seconds::*clock) {
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
        const Point &a = pts[i], &b = pts[i + 1];
        if ((a.rmse - target) * (b.rmse - target) <= 0.0) {
            const double f = std::log(target / a.rmse) / std::log(b.rmse / a.rmse);
            return a.time.*clock * std::pow(b.time.*clock / a.time.*clock, f);
        }
    }
    const Point& end = target > pts.front().rmse ? pts.front() : pts.back();
    return end.time.*clock * std::pow(end.rmse / target, 2.0);
}

}  // namespace

constexpr const char* kUsage =
    "usage: bench_cycles [SCENE.toml] [--width 320] [--height 180] [--spp 4,16,64,256]\n"
    "                    [--ref-spp 2048] [--threads 2] [--out bench-cycles/]\n"
    "       bench_cycles --rmse REF.exr TEST.exr...\n"
    "Renders the scene with foldcast and Blender's Cycles (`blender` on PATH) at each --spp and\n"
    "prints each one's RMSE against its own --ref-spp reference and the time each needs to reach\n"
    "the same RMSE (docs/benchmarks.md, \"foldcast vs Cycles\").  References are kept in --out.\n";

int run(int argc, char** argv) {
    if (argc >= 4 && std::string(argv[1]) == "--rmse") {
        for (int i = 3; i < argc; ++i) std::printf("%s %.6f\n", argv[i], rmse(argv[2], argv[i]));
        return 0;
    }
    Args args;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] {
            if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
            return std::string(argv[++i]);
        };
        if (a == "--help" || a == "-h") {
            std::fputs(kUsage, stdout);
            return 0;
        } else if (a == "--width")
            args.width = std::stoi(next());
        else if (a == "--height")
            args.height = std::stoi(next());
        else if (a == "--ref-spp")
            args.ref_spp = std::stoi(next());
        else if (a == "--threads")
            args.threads = std::stoi(next());
        else if (a == "--out")
            args.out = next();
        else if (a == "--spp") {
            args.spp.clear();
            std::stringstream ss(next());
            for (std::string t; std::getline(ss, t, ',');) args.spp.push_back(std::stoi(t));
        } else if (a.rfind("-", 0) == 0)
            throw std::runtime_error("unknown option " + a + " (--help lists them)");
        else
            args.scene = a;
    }
    fs::create_directories(args.out);
    const SceneSpec scene = load_scene(args.scene);
    const auto drape_start = std::chrono::steady_clock::now();
    const GarmentData garment = load_garment(scene);
    std::printf("foldcast's garment (drape + relaxation, not counted below): %.2f s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - drape_start).count());
    const fs::path json = args.out / "scene.json";
    const std::string export_cmd = std::string(FOLDCAST_BINARY_DIR) + "/bench/bench_cycles_export " + args.scene + " " +
                                   std::to_string(args.width) + " " + std::to_string(args.height) + " " + json.string();
    if (std::system(export_cmd.c_str()) != 0) throw std::runtime_error("export failed: " + export_cmd);

    const std::string ref_name =
        "ref" + std::to_string(args.ref_spp) + "_seed" + std::to_string(kReferenceSeed) + ".exr";
    const fs::path ref_c = args.out / ("cycles_" + ref_name);
    const fs::path ref_f = args.out / ("foldcast_" + ref_name);
    if (!fs::exists(ref_f))
        std::printf("foldcast reference %d spp: %.1f s\n", args.ref_spp,
                    render_foldcast(args, scene, garment, ref_f, args.ref_spp, false, kReferenceSeed).wall);
    if (!fs::exists(ref_c))
        std::printf("Cycles reference %d spp: %.1f s\n", args.ref_spp,
                    render_cycles(args, json, ref_c, args.ref_spp, kReferenceSeed).wall);
    std::fflush(stdout);

    // One untimed render first: foldcast's once-per-process set-up (the BSDF albedo tables,
    // lazily bound libraries) is paid here, as Blender's start-up is outside Cycles' seconds.
    render_foldcast(args, scene, garment, args.out / "foldcast_warm_up.exr", 1, false, kTestSeed);

    std::vector<Point> cyc, fc, fd;
    std::printf("%-22s %6s %9s %9s %8s\n", "renderer", "spp", "wall s", "CPU s", "RMSE");
    for (const int spp : args.spp) {
        const fs::path c = args.out / ("cycles_" + std::to_string(spp) + ".exr");
        const fs::path f = args.out / ("foldcast_" + std::to_string(spp) + ".exr");
        const fs::path d = args.out / ("foldcast_denoised_" + std::to_string(spp) + ".exr");
        // Interleaved, so both see the same machine load.
        cyc.push_back({spp, render_cycles(args, json, c, spp, kTestSeed), 0.0});
        cyc.back().rmse = rmse(ref_c, c);
        fc.push_back({spp, render_foldcast(args, scene, garment, f, spp, false, kTestSeed), 0.0});
        fc.back().rmse = rmse(ref_f, f);
        fd.push_back({spp, render_foldcast(args, scene, garment, d, spp, true, kTestSeed), 0.0});
        fd.back().rmse = rmse(ref_f, d);
        for (const auto* p : {&cyc, &fc, &fd})
            std::printf("%-22s %6d %9.2f %9.2f %8.4f\n",
                        p == &cyc  ? "cycles"
                        : p == &fc ? "foldcast"
                                   : "foldcast --denoise",
                        spp, p->back().time.wall, p->back().time.cpu, p->back().rmse);
        std::fflush(stdout);
    }
    for (const auto& [name, clock] : {std::pair{"wall-clock", &Seconds::wall}, std::pair{"CPU", &Seconds::cpu}}) {
        std::printf("\n%s time to equal RMSE (each against its own %d-spp reference)\n", name, args.ref_spp);
        std::printf("%8s %10s %10s %8s %16s %8s\n", "RMSE", "cycles s", "foldcast s", "ratio", "foldcast+dn s",
                    "ratio");
        for (const Point& p : cyc) {
            const double tc = time_for(cyc, p.rmse, clock), tf = time_for(fc, p.rmse, clock),
                         td = time_for(fd, p.rmse, clock);
            std::printf("%8.4f %10.2f %10.2f %7.2fx %16.2f %7.2fx\n", p.rmse, tc, tf, tc / tf, td, tc / td);
        }
    }
    return 0;
}

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_cycles: %s\n", e.what());
        return 2;
    }
}
