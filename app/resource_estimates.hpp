#pragma once
// Resource estimates before work: a grid, image, frame count or sample count that this
// machine cannot hold, or would work on for more than an hour (drape) or a day (a render), is
// refused up front with the estimate (exit 2), `--force` to try anyway.  Figures measured on the project's 2-core VM (docs/inputs.md).
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

// Path tracing: about 128 bytes per pixel for the image, its layers and the denoiser, and a
// million samples per second (the default scene traces 1-2 M rays per second on 2 cores).
constexpr double kTraceBytesPerPixel = 128.0;
constexpr double kSamplesPerDay = 8.64e10;

inline std::string billions(double samples) { return std::to_string(static_cast<long long>(samples / 1e9)); }

// render / turntable: the image (`buffered_frames` of them: a temporal turntable keeps 5) in
// memory, and at most a day of samples.
inline void check_render_work(long long width, long long height, long long spp, long long frames,
                              int buffered_frames, const std::string& what, bool force) {
    const double pixels = double(width) * double(height);
    require_memory(static_cast<std::uint64_t>(pixels * kTraceBytesPerPixel * buffered_frames), what,
                   "a smaller --width / --height, or --force to try anyway", force);
    const double samples = pixels * double(spp) * double(frames);
    if (samples > kSamplesPerDay && !force)
        throw InputError(what + " asks for " + billions(samples) +
                         " billion samples: more than a day at a million per second; fewer pixels, --spp or "
                         "--frames, or --force to try anyway");
}

// preview: OpenGL's multisampled colour (RGBA16F) and depth (32F), the resolved and distance
// buffers, and the float read-back and image: msaa x 12 + 80 bytes per pixel (16384 x 16384
// at --msaa 4: 34 GB).  Rasterising takes no time worth estimating.
inline void check_preview_work(long long width, long long height, int msaa, const std::string& what, bool force) {
    const double pixels = double(width) * double(height);
    require_memory(static_cast<std::uint64_t>(pixels * (12.0 * msaa + 80.0)), what,
                   "a smaller --width / --height or --msaa, or --force to try anyway", force);
}

// looks --swatches: one tile traced at a time (128 bytes per pixel) and the sheet twice
// (3 bytes per pixel, and its PNG), `tiles` tiles of `tile_pixels` each; at most a day of
// samples over the sheet.
inline void check_swatch_work(long long tiles, long long tile_width, long long tile_height, long long spp,
                              const std::string& what, bool force) {
    constexpr double kLabelHeightPx = 40.0;  // the label strip under each tile, rounded up
    const double tile_pixels = double(tile_width) * double(tile_height);
    const double sheet_pixels = double(tiles) * double(tile_width) * (double(tile_height) + kLabelHeightPx);
    require_memory(static_cast<std::uint64_t>(tile_pixels * kTraceBytesPerPixel + sheet_pixels * 6.0), what,
                   "a smaller --tile or fewer looks (--only), or --force to try anyway", force);
    const double samples = double(tiles) * tile_pixels * double(spp);
    if (samples > kSamplesPerDay && !force)
        throw InputError(what + " asks for " + billions(samples) +
                         " billion samples: more than a day at a million per second; a smaller --tile, a lower "
                         "--spp or fewer looks (--only), or --force to try anyway");
}

// batch: each image as a render (memory, and at most a day), and the shard's images together
// at most a week: beyond, more shards (--shard I/N) spread the catalogue over machines.
inline void check_batch_work(long long width, long long height, long long spp, long long images,
                             const std::string& what, bool force) {
    const double pixels = double(width) * double(height);
    require_memory(static_cast<std::uint64_t>(pixels * kTraceBytesPerPixel), what,
                   "smaller width / height in the manifest, or --force to try anyway", force);
    const double per_image = pixels * double(spp);
    if (per_image > kSamplesPerDay && !force)
        throw InputError(what + " asks for " + billions(per_image) +
                         " billion samples per image: more than a day at a million per second; smaller width, "
                         "height or spp in the manifest, or --force to try anyway");
    const double shard = per_image * double(images);
    if (shard > 7.0 * kSamplesPerDay && !force)
        throw InputError(what + ": this shard's " + std::to_string(images) + " images ask for " + billions(shard) +
                         " billion samples, more than a week at a million per second; more shards (--shard I/N), "
                         "a lower spp, or --force to try anyway");
}

}  // namespace foldcast::app
