// bench_render: how close foldcast's camera pass gets to Embree's ceiling, and what full
// path tracing costs, on one scene.  Prints rays per second for
//   (a) a raw Embree loop: one coherent primary ray per pixel, 16-wide packets in 4x4
//       blocks (RTC_INTERSECT_CONTEXT_FLAG_COHERENT), rows over TBB -- the ceiling;
//   (a1) the same with single rays (rtcIntersect1), for reference;
//   (b) foldcast's primary-visibility pass (Tracer::primary_visibility);
//   (c) full path tracing (Tracer::render) at --spp;
// and the ratios b/a and c/a.  Timed runs, best of --repeat; never asserts anything.
//   bench_render [SCENE.toml] [--width W] [--height H] [--spp S] [--threads N] [--repeat R]
#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "camera_model.hpp"
#include "foldcast/render/render.hpp"
#include "foldcast/render/studio_setup.hpp"
#include "foldcast/render/tracer.hpp"

using namespace foldcast;
using namespace foldcast::render;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// (a) / (a1): the ceiling loop, nothing but camera rays and closest hits.
double raw_embree(RTCScene scene, const Camera& camera, int w, int h, int threads, bool packets) {
    const CameraModel cam(camera, w, h);
    tbb::task_arena arena(threads);
    const auto t0 = std::chrono::steady_clock::now();
    arena.execute([&] {
        tbb::parallel_for(0, (h + 3) / 4, [&](int block_row) {
            set_ftz_daz();
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
            for (int bx = 0; bx < w; bx += 4) {
                if (packets) {
                    alignas(64) RTCRayHit16 p;
                    alignas(64) int valid[16];
                    for (int k = 0; k < 16; ++k) {
                        const int x = bx + k % 4, y = block_row * 4 + k / 4;
                        valid[k] = (x < w && y < h) ? -1 : 0;
                        Vec3f o, d;
                        cam.ray(x + 0.5f, y + 0.5f, 0.5f, 0.5f, &o, &d);
                        p.ray.org_x[k] = o.x();
                        p.ray.org_y[k] = o.y();
                        p.ray.org_z[k] = o.z();
                        p.ray.dir_x[k] = d.x();
                        p.ray.dir_y[k] = d.y();
                        p.ray.dir_z[k] = d.z();
                        p.ray.tnear[k] = 0.0f;
                        p.ray.tfar[k] = 1e30f;
                        p.ray.time[k] = 0.0f;
                        p.ray.mask[k] = 0xFFFFFFFF;
                        p.ray.id[k] = 0;
                        p.ray.flags[k] = 0;
                        p.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                    }
                    rtcIntersect16(valid, scene, &ctx, &p);
                } else {
                    for (int k = 0; k < 16; ++k) {
                        const int x = bx + k % 4, y = block_row * 4 + k / 4;
                        if (x >= w || y >= h) continue;
                        Vec3f o, d;
                        cam.ray(x + 0.5f, y + 0.5f, 0.5f, 0.5f, &o, &d);
                        RTCRayHit r;
                        r.ray.org_x = o.x();
                        r.ray.org_y = o.y();
                        r.ray.org_z = o.z();
                        r.ray.dir_x = d.x();
                        r.ray.dir_y = d.y();
                        r.ray.dir_z = d.z();
                        r.ray.tnear = 0.0f;
                        r.ray.tfar = 1e30f;
                        r.ray.time = 0.0f;
                        r.ray.mask = 0xFFFFFFFF;
                        r.ray.id = 0;
                        r.ray.flags = 0;
                        r.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                        rtcIntersect1(scene, &ctx, &r);
                    }
                }
            }
        });
    });
    return static_cast<double>(w) * h / seconds_since(t0);
}

}  // namespace

int main(int argc, char** argv) {
    std::string scene_path = std::string(FOLDCAST_SOURCE_DIR) + "/gallery/default.toml";
    int width = 1280, height = 720, spp = 4, threads = 2, repeat = 5;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return i + 1 < argc ? std::atoi(argv[++i]) : 0; };
        if (a == "--width")
            width = next();
        else if (a == "--height")
            height = next();
        else if (a == "--spp")
            spp = next();
        else if (a == "--threads")
            threads = next();
        else if (a == "--repeat")
            repeat = next();
        else
            scene_path = a;
    }
    const SceneSpec scene = load_scene(scene_path);
    const StudioSetup setup(scene, load_garment(scene));
    const Camera camera =
        frame_camera(scene.camera, {setup.framing_points(0, 0.0)}, static_cast<double>(width) / height);
    const Tracer tracer(setup.lit_scene(), setup.geometry(0, 0.0));
    auto* rtc = static_cast<RTCScene>(tracer.embree_scene());

    double a = 0, a1 = 0, b = 0;
    for (int r = 0; r < repeat; ++r) {
        a = std::max(a, raw_embree(rtc, camera, width, height, threads, true));
        a1 = std::max(a1, raw_embree(rtc, camera, width, height, threads, false));
        const auto t0 = std::chrono::steady_clock::now();
        tracer.primary_visibility(camera, width, height, threads);
        b = std::max(b, static_cast<double>(width) * height / seconds_since(t0));
    }
    TraceSettings settings;
    settings.width = width;
    settings.height = height;
    settings.spp = spp;
    settings.threads = threads;
    const RenderResult full = tracer.render(camera, settings);
    const double c = full.stats.rays_per_second();

    std::printf("scene %s, %dx%d, %d thread(s)\n", scene_path.c_str(), width, height, threads);
    std::printf("%-52s %10s %8s\n", "pass", "Mrays/s", "vs (a)");
    std::printf("%-52s %10.2f %8s\n", "(a)  raw Embree, 16-wide coherent packets (ceiling)", a / 1e6, "1.00");
    std::printf("%-52s %10.2f %8.2f\n", "(a1) raw Embree, single rays", a1 / 1e6, a1 / a);
    std::printf("%-52s %10.2f %8.2f\n", "(b)  foldcast primary visibility pass", b / 1e6, b / a);
    std::printf("%-52s %10.2f %8.2f\n", "(c)  foldcast path tracing (all rays)", c / 1e6, c / a);
    std::printf("(c) %d spp: %.2f s, %llu rays, %.2f rays per camera sample\n", spp, full.stats.seconds,
                static_cast<unsigned long long>(full.stats.rays),
                static_cast<double>(full.stats.rays) / (static_cast<double>(width) * height * spp));
    return 0;
}
