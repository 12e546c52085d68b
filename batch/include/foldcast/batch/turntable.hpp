#pragma once
// Turntables: the camera rig (camera, lights, cyclorama) orbits the garment; each frame is a
// path-traced (or, with `preview`, rasterised) still written as DIR/frame_NNNN.png, and
// complete sequences are encoded to MP4.
#include <filesystem>
#include <vector>

#include "foldcast/core/progress.hpp"
#include "foldcast/render.hpp"

namespace foldcast::batch {

using render::RenderOptions;
using render::RenderStats;
using render::SceneSpec;

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
};
struct TurntableResult {
    std::vector<std::filesystem::path> written;
    RenderStats stats;  // summed over frames
    int frames_rendered = 0;
};
// `out` ending in '/' or naming a directory: a PNG sequence DIR/frame_0000.png ...;
// `out` ending in .mp4: the PNG sequence in OUT_frames/ beside it and the MP4 when the
// range covers every frame.
TurntableResult render_turntable(const SceneSpec& scene, const std::filesystem::path& out,
                                 const TurntableOptions& options, const ProgressFn& progress = {});
// Encodes a complete PNG sequence (frame_0000.png ...) into an MP4 at `fps`.
void encode_mp4(const std::filesystem::path& frames_dir, int frame_count, double fps, const std::filesystem::path& mp4);
std::filesystem::path turntable_frame_path(const std::filesystem::path& dir, int frame);

}  // namespace foldcast::batch
