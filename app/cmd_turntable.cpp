// foldcast turntable SCENE.toml -o OUT.mp4|OUT.webm|DIR/ [--frames N | --frames A:B]
#include <algorithm>
#include <cstdio>
#include <string>

#include "commands.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/render/render.hpp"
#include "foldcast/batch/turntable.hpp"
#include "progress_bar.hpp"
#include "resource_estimates.hpp"

namespace foldcast::app {
namespace {

constexpr int kMaxTurntableFrames = 100000;

// "N" = N frames; "A:B" = frames A..B-1 of the scene's count; "A:B/N" = of N frames.
void parse_frames(const std::string& text, batch::TurntableOptions& options) {
    auto number = [&](const std::string& s) {
        std::size_t used = 0;
        int v = -1;
        try {
            v = std::stoi(s, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used != s.size() || v < 0)
            throw InputError("--frames " + text + ": expected N, A:B or A:B/N with non-negative integers");
        if (v > kMaxTurntableFrames)
            throw InputError("--frames " + text + ": at most " + std::to_string(kMaxTurntableFrames) +
                             " frames (as the scene's turntable.frames)");
        return v;
    };
    const std::size_t colon = text.find(':');
    if (colon == std::string::npos) {
        options.total_frames = number(text);
        if (options.total_frames < 1) throw InputError("--frames " + text + ": need at least 1 frame");
        return;
    }
    const std::size_t slash = text.find('/', colon);
    options.first_frame = number(text.substr(0, colon));
    options.last_frame =
        number(text.substr(colon + 1, slash == std::string::npos ? std::string::npos : slash - colon - 1));
    if (slash != std::string::npos) {
        options.total_frames = number(text.substr(slash + 1));
        // 0 would mean "the scene's count" inside TurntableOptions: not what "/0" says.
        if (options.total_frames < 1) throw InputError("--frames " + text + ": N in A:B/N must be at least 1");
    }
}

}  // namespace

Command turntable_command(CLI::App& app) {
    struct Args {
        std::string scene, out, frames, join;
        batch::VideoOptions video;
        int width = 0, height = 0, spp = 0, threads = 0;
        double noise_threshold = 0.0;
        bool quiet = false, json = false, preview = false, denoise = false, keep_raw = false, temporal = false;
        bool force = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* sub =
        app.add_subcommand("turntable",
                           "Render frames of the camera orbiting the garment: a PNG sequence and a video browsers play "
                           "(H.264 MP4 or VP9 WebM)");
    sub->add_option("scene", args->scene, "Scene file (TOML)")->required();
    sub->add_option("-o,--output", args->out,
                    "OUT.mp4 (H.264, yuv420p, +faststart) or OUT.webm (VP9), frames in OUT_frames/ beside it; or DIR/ "
                    "(PNG sequence only)")
        ->required();
    sub->add_option("--frames", args->frames,
                    "N frames in all (default: the scene's [turntable] frames, 36), or A:B to render only frames "
                    "A..B-1 (A:B/N of N) for spreading over machines");
    sub->add_option("--width", args->width, "Frame width in pixels")->check(CLI::Range(1, 16384));
    sub->add_option("--height", args->height, "Frame height in pixels")->check(CLI::Range(1, 16384));
    sub->add_option("--spp", args->spp, "Samples per pixel")->check(CLI::Range(1, 1 << 20));
    sub->add_option("--threads", args->threads, "Render threads (default: all cores)")->check(CLI::Range(1, 1024));
    sub->add_option("--join", args->join,
                    "Encode an already rendered, complete PNG sequence from this directory into -o OUT.mp4|OUT.webm "
                    "(no rendering)");
    sub->add_option("--crf", args->video.crf,
                    "Video quality, constant rate factor: lower is better and larger (default: H.264 18, VP9 31; "
                    "H.264 0..51, VP9 0..63)")
        ->check(CLI::Range(0, 63));
    sub->add_option("--video-bitrate-kbps", args->video.bitrate_kbps,
                    "Average video bitrate instead of constant quality (kbit/s)")
        ->check(CLI::Range(1, 1000000))
        ->excludes("--crf");
    sub->add_option(
           "--preset", args->video.preset,
           "H.264 speed preset (x264): ultrafast .. veryslow; slower is smaller at the same quality (default medium)")
        ->check(CLI::IsMember(
            {"ultrafast", "superfast", "veryfast", "faster", "fast", "medium", "slow", "slower", "veryslow"}));
    sub->add_flag("--denoise", args->denoise, "Denoise each frame, guided by the first hit's albedo, normal and depth");
    sub->add_flag("--keep-raw", args->keep_raw, "With --denoise: also write each frame before it (frame_NNNN.raw.png)")
        ->needs("--denoise");
    sub->add_option("--noise-threshold", args->noise_threshold,
                    "Adaptive sampling: from 4 samples on, each 4x4 block of pixels stops once its estimated error "
                    "(in sRGB display units; with --denoise, the error left after denoising) is below this, e.g. 0.02; "
                    "--spp is then the most a pixel takes")
        ->check(CLI::Range(0.0, 1.0));
    sub->add_flag("--temporal", args->temporal,
                  "Temporal filter: each frame is traced with its own samples and averaged with the same surface "
                  "points in the 2 frames on either side (moved by the known turn; rejected where depth, normal, "
                  "albedo or light disagree) before --denoise; a range A:B traces the 2 frames beyond each end too");
    sub->add_flag("--preview", args->preview,
                  "Rasterise the frames with OpenGL through EGL (fast preview) instead of path tracing")
        ->excludes("--temporal");
    sub->add_flag(
        "--json", args->json,
        "Print frames, width, height, spp, mean_spp, seconds, rays, rays_per_second, reused_paths (camera paths "
        "taken from the previous frame) as JSON");
    sub->add_flag("--quiet", args->quiet, "No progress bar");
    sub->add_flag("--force", args->force, "Render even when the memory or time estimate exceeds this machine's");
    return {sub, [args] {
                const render::SceneSpec scene = render::load_scene(args->scene);
                batch::TurntableOptions options;
                if (!args->frames.empty()) parse_frames(args->frames, options);
                if (!args->join.empty()) {
                    const int total = options.total_frames > 0 ? options.total_frames : scene.turntable_frames;
                    batch::encode_mp4(args->join, total, scene.turntable_fps, args->out, args->video);
                    if (!args->quiet) std::fprintf(stderr, "wrote %s (%d frames)\n", args->out.c_str(), total);
                    return 0;
                }
                check_scene_drape_work(scene, args->scene, args->force);
                {
                    const long long total = options.total_frames > 0 ? options.total_frames : scene.turntable_frames;
                    const long long count = options.last_frame > options.first_frame
                                                ? options.last_frame - options.first_frame
                                                : total;
                    check_render_work(args->width ? args->width : scene.width,
                                      args->height ? args->height : scene.height, args->spp ? args->spp : scene.spp,
                                      args->preview ? 0 : count, args->temporal ? 5 : 1, "turntable " + args->out,
                                      args->force);
                }
                options.render.width = args->width;
                options.render.height = args->height;
                options.render.spp = args->spp;
                options.render.threads = args->threads;
                options.render.denoise = args->denoise;
                options.render.keep_raw = args->keep_raw;
                options.render.noise_threshold = args->noise_threshold;
                options.preview = args->preview;
                options.temporal = args->temporal;
                options.video = args->video;
                batch::TurntableResult result;
                {
                    ProgressBar bar(args->quiet || args->json);
                    result = batch::render_turntable(scene, args->out, options, bar.callback());
                }
                const render::RenderStats& s = result.stats;
                if (args->json) {
                    std::printf(
                        "{\"frames\": %d, \"width\": %d, \"height\": %d, \"spp\": %d, \"mean_spp\": %.3f, "
                        "\"seconds\": %.3f, \"rays\": %llu, \"rays_per_second\": %.0f, \"reused_paths\": %llu}\n",
                        result.frames_rendered, s.width, s.height, s.spp, s.mean_spp, s.seconds,
                        static_cast<unsigned long long>(s.rays), s.rays_per_second(),
                        static_cast<unsigned long long>(s.reused_paths));
                } else if (!args->quiet) {
                    std::fprintf(stderr, "rendered %d frames (%dx%d, %d spp) in %.1f s; last written: %s\n",
                                 result.frames_rendered, s.width, s.height, s.spp, s.seconds,
                                 result.written.empty() ? "-" : result.written.back().c_str());
                }
                return 0;
            }};
}

}  // namespace foldcast::app
