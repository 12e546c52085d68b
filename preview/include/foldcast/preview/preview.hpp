#pragma once
// Fast rasterised previews through OpenGL on EGL with no display: Mesa's llvmpipe on CPU
// machines, the GPU's driver where there is one.  The path tracer never needs this.
#include <memory>
#include <vector>

#include "foldcast/core/error.hpp"
#include "foldcast/core/mesh.hpp"
#include "foldcast/render/render.hpp"
#include "foldcast/render/tracer.hpp"

namespace foldcast::preview {

// A preview draws the path tracer's scenes: its vocabulary is render's.
using render::Aov;
using render::Camera;
using render::FrameGeometry;
using render::RenderOptions;
using render::RenderResult;
using render::SceneSpec;

// No EGL display or OpenGL 3.3 core context could be made here.  The message says why.
// An InputError: the command line answers it like a request it cannot serve (exit 2).
class EglUnavailable : public InputError {
public:
    using InputError::InputError;
};

struct PreviewCamera {
    Vec3f position{0.0f, 0.0f, 3.0f};
    Vec3f target{0.0f, 0.0f, 0.0f};
    Vec3f up{0.0f, 1.0f, 0.0f};
    float vertical_fov_deg = 35.0f;
};

// The cloth shading of the path tracer, cut down to what a rasteriser does cheaply:
// Lambert + Charlie sheen + isotropic GGX, all in linear RGB.
struct PreviewMaterial {
    Vec3f base_colour{0.6f, 0.6f, 0.6f};
    float roughness = 0.8f;
    Vec3f sheen_colour{0.0f, 0.0f, 0.0f};
    float sheen_roughness = 0.5f;
    float specular = 0.5f;
};

struct PreviewObject {
    const Mesh* mesh = nullptr;  // positions, triangles, normals (computed if empty)
    PreviewMaterial material;
    bool casts_shadow = true;
};

// A point light standing in for an area light: radiant intensity in W/sr (linear RGB).
// The first light is the key light and the only one that casts shadows.
struct PreviewLight {
    Vec3f position{2.0f, 3.0f, 3.0f};
    Vec3f intensity{10.0f, 10.0f, 10.0f};
    float size_m = 0.0f;  // of the area light it stands for: softens the key light's shadows
};

struct PreviewScene {
    std::vector<PreviewObject> objects;
    std::vector<PreviewLight> lights;  // at most 4 are used
    PreviewCamera camera;
    Vec3f ambient{0.05f, 0.05f, 0.05f};   // uniform environment radiance
    Vec3f background{0.0f, 0.0f, 0.0f};   // linear RGB behind everything
    bool transparent_background = false;  // alpha 0 where nothing was drawn
    bool want_depth = true;               // false skips the depth pass (PreviewImage::depth empty)
};

struct PreviewImage {
    int width = 0;
    int height = 0;
    std::vector<float> rgba;   // linear RGB + alpha (straight), top row first
    std::vector<float> depth;  // distance from the camera in metres; +inf where empty
};

// Owns one EGL context and its framebuffers; render() may be called for many frames
// (a turntable) without re-creating them.  Not thread-safe.
class PreviewRenderer {
public:
    // Throws EglUnavailable when no EGL display / GL 3.3 core context can be made.
    PreviewRenderer(int width, int height, int msaa_samples = 4);
    ~PreviewRenderer();
    PreviewRenderer(const PreviewRenderer&) = delete;
    PreviewRenderer& operator=(const PreviewRenderer&) = delete;

    PreviewImage render(const PreviewScene& scene);
    // "OpenGL 4.5 (Core Profile) Mesa 22.3.6 on llvmpipe ..." for reports.
    const std::string& device_description() const;

private:
    struct State;
    std::unique_ptr<State> state_;
};

// The scene's still, rasterised: the same garment, studio, lights (area lights become point
// lights of the same power), auto-framed camera and output conventions (linear RGBA beauty,
// depth AOV as distance from the camera) as render_still.  Sheen is shaded, weaves are
// replaced by their average colour.  Throws EglUnavailable where EGL cannot run.
RenderResult preview_still(const SceneSpec& scene, const RenderOptions& options, int msaa_samples = 4);

// One frame of a placed studio (render::StudioSetup::geometry) through the rasteriser, as a
// RenderResult (beauty, and the depth AOV if asked): what turntables use frame by frame.
RenderResult preview_frame(PreviewRenderer& renderer, const SceneSpec& lit_scene, const FrameGeometry& geometry,
                           const Camera& camera, const std::vector<Aov>& aovs);

}  // namespace foldcast::preview
