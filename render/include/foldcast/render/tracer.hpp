#pragma once
// The path tracer over one frame's geometry: an Embree scene holding the garment and the
// studio meshes, plus the lights and materials.  Build once per frame, render any camera.
#include <memory>
#include <vector>

#include "foldcast/render/render.hpp"
#include "foldcast/render/studio.hpp"

namespace foldcast::render {

struct FrameGeometry {
    Mesh garment;                  // positions, normals, triangles, UVs (metres; may be empty)
    std::vector<float> fold_sign;  // per garment vertex, may be empty
    std::vector<StudioMesh> studio;
};

// Paths a turntable carries from frame to frame (render/src/path_reuse.hpp), in at most
// `budget_bytes` of memory: the default keeps every clear path of a 640x640 turntable at
// 16 spp (about 0.4 GB); larger or many-sample frames keep what fits, tile by tile, and a
// frame whose table of sample slots alone would take a quarter of it keeps none.  Only the
// speed depends on it, never the frames' bytes.
class PathReuse;
inline constexpr std::size_t kPathReuseBudgetBytes = std::size_t(1) << 30;
std::shared_ptr<PathReuse> make_path_reuse(std::size_t budget_bytes = kPathReuseBudgetBytes);

struct TraceSettings {
    int width = 0, height = 0, spp = 1;
    std::uint64_t seed = 1;
    int threads = 0;
    std::vector<Aov> aovs;
    bool denoise = false;
    bool keep_raw = false;
    double noise_threshold = 0.0;  // RenderOptions::noise_threshold
    double exposure_ev = 0.0;      // for the threshold's display units
    bool keep_features = false;    // RenderResult::features (turntables' temporal filter)
    // The image will be denoised after the render (the temporal filter does it): adaptive
    // sampling judges packets as it does for `denoise`, but the tracer leaves the image raw.
    bool denoised_later = false;
    // A turntable's frames, rendered one after another with one camera, seed and settings:
    // paths that missed the turning garment and supports are kept for the next frame and
    // taken there where the turned meshes still miss them (the same bytes as tracing them).
    std::shared_ptr<PathReuse> reuse;
};
// The settings a still or turntable frame renders with: the options over the scene's.
TraceSettings trace_settings(const SceneSpec& scene, const RenderOptions& options);

class Tracer {
public:
    Tracer(const SceneSpec& scene, FrameGeometry geometry);
    ~Tracer();
    Tracer(const Tracer&) = delete;
    Tracer& operator=(const Tracer&) = delete;

    RenderResult render(const Camera& camera, const TraceSettings& settings, const ProgressFn& progress = {}) const;

    // Primary visibility only (packets of 16 coherent camera rays, closest hit, no
    // shading): the benchmark's "foldcast primary pass".  Returns the number of hits.
    std::uint64_t primary_visibility(const Camera& camera, int width, int height, int threads) const;
    // The raw Embree scene handle (RTCScene) for the benchmark's ceiling loop.
    void* embree_scene() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// What render() does after tracing when TraceSettings::denoise is set, for a turntable's
// frame traced with keep_features (and denoised_later, so that adaptive sampling judged it
// alike): keeps the image as `raw` when asked, then denoises it as a frame, without the
// stages only a still can afford (the turntable's 40 s budget, issue #16;
// render/src/denoise/denoise.hpp).  A turntable calls it on one thread for frame f while frame f+1
// traces on the others.
void denoise_traced(RenderResult& result, bool keep_raw, int threads);

// Puts the render thread into flush-to-zero / denormals-are-zero mode (Embree's advice).
void set_ftz_daz();

}  // namespace foldcast::render
