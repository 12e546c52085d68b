#pragma once
// Resource estimates before work: a grid, image, frame count or sample count that this
// machine cannot hold, or would work on for more than an hour (drape) or a day (a render), is
// refused up front with the estimate (exit 2),
// `--force` to try anyway.  Figures measured on the project's 2-core VM (docs/inputs.md).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "foldcast/core/error.hpp"
#include "foldcast/core/resources.hpp"
#include "foldcast/render/render.hpp"

namespace foldcast::app {

// drape: about 700 bytes per grid vertex (512x512: 252 MB peak), plus the animation's
// frames twice; 40 s at 512x512, growing as vertices^1.4 (about an hour at 2,500 x 2,500).
inline void check_drape_work(int nu, int nv, int frames, const std::string& what, bool force) {
    const double vertices = double(nu) * double(nv);
    require_memory(static_cast<std::uint64_t>(vertices * 700.0 + vertices * double(frames) * 24.0), what,
                   "a smaller --grid or fewer --frames, or --force to try anyway", force);
    const double hours = 40.0 * std::pow(vertices / (512.0 * 512.0), 1.4) / 3600.0;
    if (hours > 1.0 && !force)
        throw InputError(what + " would take about " + std::to_string(static_cast<long long>(hours)) +
                         " hours here (512x512 takes 40 s); a smaller grid, or --force to try anyway");
}

// A scene whose garment is draped: the same estimate for its grid and frames, named by the
// scene file and key.
inline void check_scene_drape_work(const render::SceneSpec& scene, const std::string& scene_path, bool force) {
    if (scene.garment.source != render::GarmentSpec::Source::drape) return;
    check_drape_work(scene.garment.grid_nu, scene.garment.grid_nv, std::max(1, scene.garment.animation_frames),
                     scene_path + ": garment.grid = [" + std::to_string(scene.garment.grid_nu) + ", " +
                         std::to_string(scene.garment.grid_nv) + "]",
                     force);
}

// render / turntable: about 128 bytes per pixel for the image, its layers and the denoiser
// (`buffered_frames` of them: a temporal turntable keeps 5), and a day at one million
// samples per second (the default scene traces 1-2 M rays per second on 2 cores).
inline void check_render_work(long long width, long long height, long long spp, long long frames,
                              int buffered_frames, const std::string& what, bool force) {
    const double pixels = double(width) * double(height);
    require_memory(static_cast<std::uint64_t>(pixels * 128.0 * buffered_frames), what,
                   "a smaller --width / --height, or --force to try anyway", force);
    const double samples = pixels * double(spp) * double(frames);
    if (samples > 8.64e10 && !force)
        throw InputError(what + " asks for " + std::to_string(static_cast<long long>(samples / 1e9)) +
                         " billion samples: more than a day at a million per second; fewer pixels, --spp or "
                         "--frames, or --force to try anyway");
}

}  // namespace foldcast::app
