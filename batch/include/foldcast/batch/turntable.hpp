#pragma once
// Turntables: the camera rig (camera, lights, cyclorama) orbits the garment; each frame is a
// path-traced (or, with `preview`, rasterised) still written as DIR/frame_NNNN.png, and
// complete sequences are encoded to a video that browsers play (H.264 MP4 or VP9 WebM,
// through Debian's ffmpeg).
#include <filesystem>
#include <string>
#include <vector>

#include "foldcast/core/progress.hpp"
#include "foldcast/render/render.hpp"

namespace foldcast::batch {

using render::RenderOptions;
using render::RenderStats;
using render::SceneSpec;

// The video's codec follows its extension: .mp4 H.264 (libx264), .webm VP9 (libvpx-vp9).
enum class VideoCodec { h264, vp9 };
struct VideoOptions {
    int crf = -1;          // constant quality, lower is better; -1 = the codec's default (default_crf)
    int bitrate_kbps = 0;  // > 0: this average bitrate instead of constant quality
    std::string preset;    // H.264 only: x264's speed preset; empty = "medium"
};
// Throws InputError naming `video` unless it ends in .mp4 or .webm.
VideoCodec video_codec_for(const std::filesystem::path& video);
int default_crf(VideoCodec codec);  // H.264 18, VP9 31: frames indistinguishable from their PNGs at a glance
// Throws InputError naming `video`, the value and what is allowed (the codec is `video`'s).
void check_video_options(const VideoOptions& options, const std::filesystem::path& video);

struct TurntableOptions {
    RenderOptions render;
    int total_frames = 0;  // 0 = the scene's turntable_frames
    int first_frame = 0;   // render frames [first_frame, last_frame)
    int last_frame = -1;   // -1 = total_frames
    bool preview = false;  // rasterise each frame through EGL instead of path tracing
    // Path tracing: average each frame with its neighbours' surface points (render's
    // temporal_filter.hpp), tracing every frame with its own samples; off: frames are
    // independent stills, all traced with the same per-pixel samples.
    bool temporal = false;
    int msaa_samples = 4;  // preview only
    VideoOptions video;
};
struct TurntableResult {
    std::vector<std::filesystem::path> written;
    RenderStats stats;  // summed over frames
    int frames_rendered = 0;
};
// `out` ending in '/' or naming a directory: a PNG sequence DIR/frame_0000.png ...;
// `out` ending in .mp4 or .webm: the PNG sequence in OUT_frames/ beside it and the video
// when the range covers every frame.  The orbit's last frame is one step before the first
// (frame f turns by 360 f / N degrees), so the video loops without a repeated frame.
TurntableResult render_turntable(const SceneSpec& scene, const std::filesystem::path& out,
                                 const TurntableOptions& options, const ProgressFn& progress = {});
// Encodes a complete PNG sequence (frame_0000.png ...) into a video (.mp4 or .webm) at `fps`.
void encode_mp4(const std::filesystem::path& frames_dir, int frame_count, double fps, const std::filesystem::path& mp4,
                const VideoOptions& video = {});
std::filesystem::path turntable_frame_path(const std::filesystem::path& dir, int frame);

}  // namespace foldcast::batch
