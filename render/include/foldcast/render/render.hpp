#pragma once
// render: scene files, the studio and an Embree path tracer for garment stills (docs/render.md).
//
// A scene file (TOML) names the garment (inline drape parameters, or an .obj / .pc2 / .fca
// file and frame), the look, the camera, the lights, the backdrop and the output settings.
// load_scene() reads it; render_still() does the work (turntables: foldcast/batch/turntable.hpp).
//
// World frame: y up, the garment hangs in the x-y plane facing +z (drape's frame), the
// cyclorama floor and wall sit below and behind it.  Lengths in metres, colours linear RGB.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "foldcast/core/mesh.hpp"
#include "foldcast/core/progress.hpp"
#include "foldcast/looks/looks.hpp"

namespace foldcast {
class OutputTransaction;  // foldcast/core/atomic_file.hpp
}

namespace foldcast::render {

struct CameraSpec {
    bool auto_frame = true;            // place the camera so the garment fills frame_share
    double frame_share = 0.75;         // share of the frame's limiting side the garment's bbox spans
    double azimuth_deg = 0.0;          // orbit angle about the vertical axis; 0 = in front (+z)
    double elevation_deg = 4.0;        // above the garment's centre
    Vec3f position{0.0f, 0.0f, 2.0f};  // used when auto_frame is false
    Vec3f target{0.0f, 0.0f, 0.0f};
    double fov_deg = 30.0;          // vertical field of view
    double aperture_m = 0.0;        // thin-lens aperture diameter; 0 = pinhole
    double focus_distance_m = 0.0;  // 0 = focus on the target
};

// A one-sided rectangular area light facing its target.
struct AreaLight {
    std::string name;
    Vec3f position{0.0f, 1.0f, 1.0f};
    Vec3f target{0.0f, 0.0f, 0.0f};
    float width_m = 0.5f;
    float height_m = 0.5f;
    Vec3f radiance{10.0f, 10.0f, 10.0f};  // W/(m^2 sr), linear RGB
};

struct GarmentSpec {
    enum class Source { drape, obj, pc2, fca };
    Source source = Source::drape;
    // Source::drape: cloth size and supports, folded by drape with the look's mechanics.
    double width_m = 0.6;
    double height_m = 0.8;
    double inset_m = 0.12;
    int supports = 2;             // equally spaced under the top edge (drape's --supports)
    double support_drop_m = 0.0;  // the last support this much lower than the first
    std::string closure = "hem";  // drape's --closure: hem or paper
    int grid_nu = 96;
    int grid_nv = 128;
    int animation_frames = 0;  // > 0: turntables sway the drape over this many frames
    double sway_amplitude_m = 0.0;
    bool relax = true;  // relax the drape towards isometry (docs/drape.md)
    // Files: .obj (a mesh), .pc2 (+ the .obj topology of the same stem, or `topology`), .fca.
    std::filesystem::path path;
    std::filesystem::path topology;
    int frame = 0;       // stills use this frame of an animation
    double scale = 1.0;  // multiplies file positions (to metres)
};

struct SceneSpec {
    std::filesystem::path file;  // where it was read from ("" if built in code)
    GarmentSpec garment;
    looks::Look look;
    CameraSpec camera;
    std::vector<AreaLight> lights;        // explicit area lights
    bool studio_preset = true;            // add key/fill/rim lights placed around the garment
    Vec3f environment{0.0f, 0.0f, 0.0f};  // uniform environment radiance
    enum class Backdrop { cyclorama, none };
    Backdrop backdrop = Backdrop::cyclorama;
    Vec3f backdrop_colour{0.8f, 0.8f, 0.8f};
    bool transparent = false;  // camera rays that see the backdrop or the sky get alpha 0
    enum class Supports { rod, clips, none };
    Supports supports = Supports::rod;
    int width = 1280;
    int height = 720;
    int spp = 64;
    std::uint64_t seed = 1;
    int max_depth = 5;  // path vertices after the camera
    double exposure_ev = 0.0;
    int turntable_frames = 36;
    double turntable_fps = 24.0;
};

// Reads a scene file.  Unknown keys, wrong types and bad values throw InputError naming the
// file, line and key.  Relative paths inside are resolved against the file's folder.
SceneSpec load_scene(const std::filesystem::path& file);
// The studio light preset: key, fill and rim area lights around a garment centred at
// `centre` whose largest side is `size_m`.
std::vector<AreaLight> studio_lights(const Vec3f& centre, double size_m);

// The garment the scene names, as an animation (one frame for still sources), with a
// per-vertex fold sign in [-1, 1] (drape's, or estimated from the geometry for files) and
// the vertices the rod or clips hold (drape's supports; for files the top corners).
struct GarmentData {
    Animation animation;
    std::vector<std::vector<float>> fold_sign;  // per frame, per vertex
    std::vector<std::uint32_t> support_vertices;
};
GarmentData load_garment(const SceneSpec& scene, const ProgressFn& progress = {});

// Fold sign estimated from geometry: which side of a smoothed version of the surface each
// vertex lies on, in units of the local fold depth, clamped to [-1, 1].
std::vector<float> fold_sign_from_geometry(const Mesh& mesh);

struct Camera {
    Vec3f position{0.0f, 0.0f, 2.0f};
    Vec3f target{0.0f, 0.0f, 0.0f};
    Vec3f up{0.0f, 1.0f, 0.0f};
    double fov_deg = 30.0;
    double aperture_m = 0.0;
    double focus_distance_m = 1.0;
};
// The scene's camera for an image of this aspect (width / height).  Auto-framing places it
// so the projected bounding box of all the points of all `fit_frames` spans
// spec.frame_share of the frame's limiting side, centred.
Camera frame_camera(const CameraSpec& spec, const std::vector<std::vector<Vec3f>>& fit_frames, double aspect);
// Projects a world point to pixel coordinates (x right, y down); false if behind the camera.
bool project(const Camera& camera, int width, int height, const Vec3f& point, Eigen::Vector2d* pixel);

enum class Aov { albedo, normal, depth, fold };
// "albedo,normal" -> list; throws InputError naming the flag value and listing allowed names.
std::vector<Aov> parse_aovs(const std::string& list);
const char* aov_name(Aov aov);

struct RenderOptions {
    int width = 0;  // 0 = the scene's
    int height = 0;
    int spp = 0;
    std::optional<std::uint64_t> seed;
    int threads = 0;  // 0 = all cores
    std::vector<Aov> aovs;
    // Feature-guided denoising (albedo, normal and depth of the first hit guide it; the
    // weave and prints are kept by filtering only the light they receive).
    bool denoise = false;
    bool keep_raw = false;  // with denoise: RenderResult::raw keeps the image before it
    // Adaptive sampling when > 0: a pixel stops once the standard error of its mean, in
    // sRGB display units (0-1, exposure applied), is below this; spp is then the most any
    // pixel takes.  Checked after 16, 32, 64 ... samples.
    double noise_threshold = 0.0;
};

// Linear float image, row-major from the top, `channels` floats per pixel.
struct Image {
    int width = 0;
    int height = 0;
    int channels = 0;
    std::vector<float> pixels;
    float* at(int x, int y) { return &pixels[(static_cast<std::size_t>(y) * width + x) * channels]; }
    const float* at(int x, int y) const { return &pixels[(static_cast<std::size_t>(y) * width + x) * channels]; }
};

struct AovImage {
    Aov aov;
    Image image;
};

struct RenderStats {
    int width = 0;
    int height = 0;
    int spp = 0;            // samples per pixel asked for (the most, when adaptive)
    double mean_spp = 0.0;  // samples per pixel taken, on average
    // ... over the pixels whose camera rays mostly hit the garment, and over all the others
    // (backdrop, supports, sky): where adaptive sampling spent its samples (0 without pixels).
    double garment_mean_spp = 0.0, backdrop_mean_spp = 0.0;
    double seconds = 0.0;
    std::uint64_t rays = 0;  // every ray traced: camera, bounce and shadow
    std::uint64_t reused_paths = 0;  // camera paths taken from the previous turntable frame
    double rays_per_second() const { return seconds > 0.0 ? static_cast<double>(rays) / seconds : 0.0; }
};

// What each pixel's camera rays hit first, as means over its samples (row-major like
// Image): what the denoiser is guided by, and what a turntable's temporal filter matches
// between frames (temporal_filter.hpp).
struct PixelFeatures {
    std::vector<Vec3f> albedo;      // first-hit BSDF albedo
    std::vector<Vec3f> normal;      // unit shading normal, zero where the sky was seen
    std::vector<float> depth;       // first-hit distance from the camera, 0 for the sky
    std::vector<float> turning;     // share of samples that hit the garment or its supports
    std::vector<float> cloth;       // share of samples that hit the garment
    std::vector<float> variance;    // of the pixel's mean luminance (its samples' spread / n)
    // The colour of the first half of the pixel's samples and of the rest, and the first
    // half's share of them: two estimates with separate noise for the denoiser's
    // cross-filtering.  Empty where not kept (below 2 spp, or not denoised): the denoiser
    // then filters the colour alone.
    std::vector<Vec3f> half_a, half_b;
    std::vector<float> half_share;
    // A still's two layers per pixel, its samples split by the surface they hit first
    // (render/src/pixel_layers.hpp): layer 1's share of the samples (0 where the pixel saw one
    // surface), and each layer's mean colour, albedo, unit shading normal and depth.  Empty
    // where not kept (turntable frames, transparent renders).  layer_metal: 1 where either
    // layer is mostly the rod's or a wire's metal.
    std::vector<float> layer_share;
    std::vector<std::uint8_t> layer_metal;
    std::vector<Vec3f> layer_colour[2], layer_albedo[2], layer_normal[2];
    std::vector<float> layer_depth[2];
};

struct RenderResult {
    Image beauty;              // RGBA, linear, straight (not premultiplied) alpha
    std::optional<Image> raw;  // before denoising, when asked to keep it
    std::vector<AovImage> aovs;
    std::optional<PixelFeatures> features;  // when TraceSettings::keep_features
    RenderStats stats;
};

// Renders the scene's still (garment.frame).  Deterministic: the same scene, seed and spp
// give the same pixels whatever `threads` is.
RenderResult render_still(const SceneSpec& scene, const RenderOptions& options, const ProgressFn& progress = {});
// The same with the garment already loaded (load_garment): its seconds then count the
// studio, the BVH and the render only (benchmarks that time the renderer alone use it).
RenderResult render_still(const SceneSpec& scene, GarmentData garment, const RenderOptions& options,
                          const ProgressFn& progress = {});

// Writes OUT.png (8-bit sRGB; with alpha when the scene is transparent) or OUT.exr (linear
// float RGBA), each AOV beside it as OUT.<aov>.png / OUT.<aov>.exr and the image before
// denoising, when kept, as OUT.raw.png / OUT.raw.exr.  Atomic writes.
// Returns the paths written.
std::vector<std::filesystem::path> write_render(const std::filesystem::path& out, const RenderResult& result,
                                                const SceneSpec& scene);
// The same files staged in `outputs`, replaced when the caller commits it.
std::vector<std::filesystem::path> write_render(OutputTransaction& outputs, const std::filesystem::path& out,
                                                const RenderResult& result, const SceneSpec& scene);
// sRGB 8-bit encoding used for PNG output (exposure applied, clamped).
std::vector<std::uint8_t> to_srgb8(const Image& rgba, double exposure_ev, bool keep_alpha);

}  // namespace foldcast::render
