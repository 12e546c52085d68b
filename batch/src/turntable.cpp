// Turntables: the camera rig (camera, lights, cyclorama) orbits the garment; each frame is a
// still written as DIR/frame_NNNN.png, and complete sequences are encoded to a video.
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <future>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/batch/turntable.hpp"
#include "foldcast/preview/preview.hpp"
#include "foldcast/render/studio_setup.hpp"
#include "foldcast/render/tracer.hpp"
#include "video_stream.hpp"
#include "temporal_window.hpp"

namespace foldcast::batch {
namespace fs = std::filesystem;

using preview::preview_frame;
using preview::PreviewRenderer;
using render::Camera;
using render::FrameGeometry;
using render::load_garment;
using render::RenderResult;
using render::StudioSetup;
using render::Tracer;
using render::TraceSettings;
using render::write_render;

fs::path turntable_frame_path(const fs::path& dir, int frame) {
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%04d.png", frame);
    return dir / name;
}

namespace {
// Frame f's seed when every frame has its own samples: the sampler hashes the seed with the
// pixel (render's sobol_sampler.hpp), so distinct odd multiples are enough to decorrelate.
std::uint64_t render_frame_seed(std::uint64_t seed, int frame) {
    return seed + 0x9e3779b97f4a7c15ULL * (2 * static_cast<std::uint64_t>(frame) + 1);
}

// Frame f's PNG: the one this run staged in `outputs`, else the file an earlier run left.
fs::path frame_to_read(OutputTransaction& outputs, const fs::path& frames_dir, int f) {
    const fs::path final_path = turntable_frame_path(frames_dir, f);
    const fs::path staged = outputs.staged(final_path);
    return staged.empty() ? final_path : staged;
}

void stage_mp4(OutputTransaction& outputs, const fs::path& frames_dir, int frame_count, double fps, const fs::path& mp4,
               const VideoOptions& video) {
    check_writable(mp4);
    cv::Mat first = cv::imread(frame_to_read(outputs, frames_dir, 0).string(), cv::IMREAD_COLOR);
    if (first.empty()) throw InputError("turntable frames in " + frames_dir.string() + ": frame_0000.png is missing");
    VideoStream stream(outputs, mp4, fps, first.size(), video);
    for (int f = 0; f < frame_count; ++f) {
        const fs::path p = turntable_frame_path(frames_dir, f);
        cv::Mat img = cv::imread(frame_to_read(outputs, frames_dir, f).string(), cv::IMREAD_COLOR);
        if (img.empty())
            throw InputError("turntable frames in " + frames_dir.string() + ": " + p.filename().string() +
                             " is missing (render every range with --frames A:B first)");
        if (img.cols != first.cols || img.rows != first.rows)
            throw InputError(p.string() + ": size differs from frame_0000.png");
        stream.add(img);
    }
    stream.close();
}

// Every frame allocates and frees the same buffers (the beauty, the first-hit features and
// halves, the denoiser's guide and passes: tens of MB at 640x640).  By default glibc maps
// blocks that large on their own and returns them to the kernel when freed, so each frame
// page-faulted them in again and the kernel zeroed every page: about 15k faults and 0.1 s of
// system time a 640x640 frame on two threads.  Kept in the heap instead, later frames reuse
// them (5k faults, 0.045 s).  Allocation only: the frames are the same bytes.
void keep_freed_frame_buffers() {
#if defined(__GLIBC__)
    mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest; blocks below it come from the heap
    mallopt(M_TRIM_THRESHOLD, 1 << 30);   // and freed ones stay there for the next frame
#endif
}

// A frame as its PNG holds it (8-bit sRGB, no alpha), in OpenCV's BGR order for the MP4.
cv::Mat video_frame(const render::Image& beauty, const SceneSpec& opaque) {
    std::vector<std::uint8_t> rgb = render::to_srgb8(beauty, opaque.exposure_ev, false);
    cv::Mat bgr;
    cv::cvtColor(cv::Mat(beauty.height, beauty.width, CV_8UC3, rgb.data()), bgr, cv::COLOR_RGB2BGR);
    return bgr;
}
}  // namespace

void encode_mp4(const fs::path& frames_dir, int frame_count, double fps, const fs::path& mp4,
                const VideoOptions& video) {
    check_video_options(video, mp4);
    OutputTransaction outputs;
    stage_mp4(outputs, frames_dir, frame_count, fps, mp4, video);
    outputs.commit();
}

namespace {
// Frames an earlier, longer turntable left in the frame folder (frame_NNNN.png with N past
// this one's count) would sit beside the new set as if they belonged to it: they go with the
// commit that puts the new set in place, in its interrupt-protected window.
void remove_stale_frames_on_commit(OutputTransaction& outputs, const fs::path& dir, int total) {
    std::error_code ec;
    std::vector<fs::path> stale;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        int index = -1;
        char tail[8] = {};
        if (std::sscanf(name.c_str(), "frame_%d%7s", &index, tail) == 2 && std::string(tail) == ".png" &&
            index >= total && turntable_frame_path(dir, index).filename() == name)
            stale.push_back(it->path());
    }
    for (const fs::path& p : stale) outputs.remove_on_commit(p);
}
}  // namespace

namespace {

// Where a turntable goes: a video (its frames in OUT_frames/ beside it) or a folder of frames.
// Checked, and the frame folder made, before any rendering.
struct TurntableTarget {
    bool to_video = false;
    fs::path frame_dir;
};

TurntableTarget prepare_target(const fs::path& out, const TurntableOptions& options) {
    const std::string ext = out.extension().string();
    const bool to_mp4 = ext == ".mp4" || ext == ".webm";
    const std::string out_s = out.string();
    const bool to_dir = !to_mp4 && (out_s.empty() || out_s.back() == '/' || fs::is_directory(out) || ext.empty());
    if (!to_mp4 && !to_dir)
        throw InputError("turntable output '" + out_s + "': a turntable goes to OUT.mp4, OUT.webm or a directory DIR/");
    if (to_mp4) check_video_options(options.video, out);  // before any folder is made
    if (!to_mp4 && (options.video.crf >= 0 || options.video.bitrate_kbps > 0 || !options.video.preset.empty()))
        throw InputError("turntable output '" + out_s +
                         "': video quality, bitrate and preset need OUT.mp4 or OUT.webm");
    TurntableTarget target{to_mp4, to_mp4 ? fs::path(out).replace_extension("").concat("_frames") : out};
    std::error_code ec;
    fs::create_directories(target.frame_dir, ec);
    if (!fs::is_directory(target.frame_dir))
        throw InputError("turntable output '" + out_s + "': cannot create the frame directory " +
                         target.frame_dir.string());
    if (to_mp4) check_writable(out);
    return target;
}

// What the render loop traces with: when the finishing thread denoises, the trace keeps the
// features that guide it and judges its packets as for denoising.
TraceSettings frame_trace_settings(const TraceSettings& settings, const TurntableOptions& options,
                                   bool denoise_in_finish) {
    TraceSettings trace_only = settings;
    if (denoise_in_finish) {
        trace_only.denoise = false;
        trace_only.keep_raw = false;
        trace_only.denoised_later = true;  // adaptive sampling judges the packets as for denoise
        trace_only.keep_features = true;   // what the finishing thread's denoiser is guided by
    }
    // Frames traced in order with one camera and seed: each takes the previous frame's paths
    // that the turned garment and supports still miss (the same bytes, less tracing).
    if (!options.preview && !options.temporal) trace_only.reuse = render::make_path_reuse();
    return trace_only;
}

// The frames this run renders, [first, last) of the turntable's `total`.
std::pair<int, int> frame_range(const TurntableOptions& options, int total) {
    const int first = options.first_frame;
    const int last = options.last_frame < 0 ? total : options.last_frame;
    if (first < 0 || first >= last || last > total)
        throw InputError("turntable frames " + std::to_string(first) + ":" + std::to_string(last) +
                         ": need 0 <= first < last <= " + std::to_string(total) + " (the turntable's frame count)");
    return {first, last};
}

}  // namespace

TurntableResult render_turntable(const SceneSpec& scene, const fs::path& out, const TurntableOptions& options,
                                 const ProgressFn& progress) {
    const auto start = std::chrono::steady_clock::now();
    const int total = options.total_frames > 0 ? options.total_frames : scene.turntable_frames;
    const std::pair<int, int> range = frame_range(options, total);
    const int first = range.first, last = range.second;
    const TurntableTarget target = prepare_target(out, options);
    const bool to_mp4 = target.to_video;
    const fs::path& dir = target.frame_dir;
    keep_freed_frame_buffers();

    const StudioSetup setup(scene, load_garment(scene));
    const int width = options.render.width > 0 ? options.render.width : scene.width;
    const int height = options.render.height > 0 ? options.render.height : scene.height;
    // Its frames are denoised by denoise_traced or the temporal filter, without the stills'
    // stages (render/src/denoise/denoise.hpp).
    const TraceSettings settings = trace_settings(scene, options.render);
    const bool animated = setup.frame_count() > 1;
    auto garment_frame = [&](int f) {
        return animated ? f % setup.frame_count() : std::min(scene.garment.frame, setup.frame_count() - 1);
    };
    auto turn = [&](int f) { return -360.0 * f / total; };  // garment turns back = rig orbits forward
    // One framing for the whole orbit (no zoom pumping): fit every 10 degrees of turn over
    // the frames the animation uses.
    std::vector<std::vector<Vec3f>> fit;
    for (int k = 0; k < 36; ++k) fit.push_back(setup.framing_points(garment_frame(k * total / 36), -10.0 * k));
    const Camera camera = frame_camera(scene.camera, fit, static_cast<double>(width) / height);

    TurntableResult result;
    // This run's frames and the MP4 replace the old ones together when every frame is done.
    OutputTransaction outputs;
    // Frame f is finished on a second thread while frame f+1 renders: denoised (path traced
    // frames with --denoise; its serial set-up and the next frame's single-threaded BVH build
    // then overlap the other's parallel work instead of idling cores) and written (sRGB, PNG).
    // At most one frame is in flight, so memory stays at two frames and a failed write stops
    // the loop.  Each step's output depends only on its input: the same bytes as in sequence.
    const bool denoise_in_finish = settings.denoise && !options.preview && !options.temporal;
    const TraceSettings trace_only = frame_trace_settings(settings, options, denoise_in_finish);
    SceneSpec opaque = setup.lit_scene();
    opaque.transparent = false;  // video frames have no alpha
    // The whole orbit to an MP4: each frame is encoded right after its PNG is written.
    std::unique_ptr<VideoStream> mp4;
    if (to_mp4 && first == 0 && last == total)
        mp4 = std::make_unique<VideoStream>(outputs, out, scene.turntable_fps, cv::Size(width, height), options.video);
    std::future<void> writing;  // after what its task uses: waits for the task when destroyed early
    std::unique_ptr<PreviewRenderer> rasteriser;
    if (options.preview) rasteriser = std::make_unique<PreviewRenderer>(width, height, options.msaa_samples);
    std::unique_ptr<TemporalWindow> window;
    int traced = 0;  // frames path traced (with the temporal filter, up to 2r more than written)
    if (options.temporal && !options.preview) {
        const int radius = std::min(render::kTemporalRadius, (total - 1) / 2);
        window = std::make_unique<TemporalWindow>(total, last, radius, [&](int g) {
            // Each frame its own samples (seed and frame hashed): the neighbours the filter
            // averages then carry independent noise, on the still backdrop too.
            TraceSettings s = settings;
            s.seed = render_frame_seed(settings.seed, g);
            s.keep_features = true;
            s.denoised_later = s.denoise;
            s.denoise = false;  // the filter denoises the average
            s.keep_raw = false;
            RenderResult r = Tracer(setup.lit_scene(), setup.geometry(garment_frame(g), turn(g))).render(camera, s);
            return TracedFrame{{std::move(r.beauty), std::move(*r.features), turn(g)}, r.stats};
        });
    }
    for (int f = first; f < last; ++f) {
        const int done = f - first, count = last - first;
        ProgressFn frame_progress;
        if (progress)
            frame_progress = [&, done, count](std::string_view, double fraction) {
                progress("turntable", (done + fraction) / count);
            };
        RenderResult r;
        if (window) {
            TemporalWindow::Output o =
                window->output(f, camera, setup.turn_centre(), settings.denoise, settings.keep_raw, settings.threads);
            r = std::move(o.result);
            traced += o.traced;
            if (progress) progress("turntable", (done + 1.0) / count);
        } else {
            const FrameGeometry geometry = setup.geometry(garment_frame(f), turn(f));
            r = rasteriser ? preview_frame(*rasteriser, setup.lit_scene(), geometry, camera, {})
                           : Tracer(setup.lit_scene(), geometry).render(camera, trace_only, frame_progress);
            if (rasteriser && progress) progress("turntable", (done + 1.0) / count);
            ++traced;
        }
        result.stats.rays += r.stats.rays;
        result.stats.reused_paths += r.stats.reused_paths;
        result.stats.mean_spp += r.stats.mean_spp;
        auto frame = std::make_shared<RenderResult>();
        frame->beauty = std::move(r.beauty);
        frame->raw = std::move(r.raw);
        if (denoise_in_finish) frame->features = std::move(r.features);
        const fs::path p = turntable_frame_path(dir, f);
        if (writing.valid()) writing.get();
        writing = std::async(std::launch::async, [frame, p, &opaque, &outputs, &settings, &mp4] {
            if (frame->features) {
                render::denoise_traced(*frame, settings.keep_raw, settings.threads);
                frame->features.reset();  // the PNG is the beauty (and raw) only
            }
            write_render(outputs, p, *frame, opaque);
            if (mp4) mp4->add(video_frame(frame->beauty, opaque));
        });
        result.written.push_back(p);
        ++result.frames_rendered;
    }
    if (writing.valid()) writing.get();
    if (mp4) {
        mp4->close();
        result.written.push_back(out);
    }
    remove_stale_frames_on_commit(outputs, dir, total);
    outputs.commit();
    result.stats.width = width;
    result.stats.height = height;
    result.stats.spp = settings.spp;
    result.stats.mean_spp /= traced;
    result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace foldcast::batch
