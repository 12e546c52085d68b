#include "preview_scene.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <string>

#include "foldcast/core/error.hpp"
#include "foldcast/looks/weave.hpp"
#include "foldcast/render/studio_setup.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::preview {

using render::aov_name;
using render::AreaLight;
using render::frame_camera;
using render::Image;
using render::load_garment;
using render::MaterialId;
using render::StudioMesh;
using render::StudioSetup;

namespace {

// Far beyond any weave period: sample_weave returns the weave's average.
constexpr double kAverageFootprint_m = 1.0;

PreviewMaterial garment_material(const looks::Appearance& a) {
    PreviewMaterial m;
    m.base_colour = looks::weave_albedo(a, looks::sample_weave(a, Eigen::Vector2d::Zero(), kAverageFootprint_m));
    m.roughness = static_cast<float>(a.roughness);
    m.sheen_colour = a.sheen_colour;
    m.sheen_roughness = static_cast<float>(a.sheen_roughness);
    m.specular = static_cast<float>(a.specular);
    return m;
}

// The tracer's studio materials (tracer.cpp), cut down to the preview's parameters.
PreviewMaterial studio_material(MaterialId id, const SceneSpec& scene) {
    PreviewMaterial m;
    m.specular = 0.25f;
    switch (id) {
        case MaterialId::backdrop:
            m.base_colour = scene.backdrop_colour;
            m.roughness = 0.9f;
            break;
        case MaterialId::metal:
            m.base_colour = Vec3f::Constant(0.02f);
            m.roughness = 0.3f;
            m.specular = 1.0f;
            break;
        case MaterialId::wood:
            m.base_colour = Vec3f(0.60f, 0.43f, 0.27f);
            m.roughness = 0.55f;
            break;
        default:
            m.base_colour = Vec3f::Constant(0.03f);
            m.roughness = 0.35f;
            break;
    }
    return m;
}

}  // namespace

std::vector<Mesh> studio_meshes(const FrameGeometry& geometry) {
    std::vector<Mesh> meshes;
    for (const StudioMesh& s : geometry.studio) {
        Mesh m;
        m.positions = s.positions;
        m.normals = s.normals;
        m.topology.triangles = s.triangles;
        meshes.push_back(std::move(m));
    }
    return meshes;
}

PreviewScene make_preview_scene(const SceneSpec& lit_scene, const FrameGeometry& geometry,
                                const std::vector<Mesh>& studio, const Camera& camera) {
    PreviewScene p;
    p.objects.push_back({&geometry.garment, garment_material(lit_scene.look.appearance), true});
    for (std::size_t i = 0; i < studio.size(); ++i) {
        const MaterialId id = geometry.studio[i].material;
        // A transparent scene shows no backdrop (the tracer gives it alpha 0).  The cyclorama
        // and the wires (which run far up out of frame) receive shadows but cast none, so the
        // shadow map spans just the garment and its clips.
        if (id == MaterialId::backdrop && lit_scene.transparent) continue;
        const bool casts = id != MaterialId::backdrop && id != MaterialId::wire;
        p.objects.push_back({&studio[i], studio_material(id, lit_scene), casts});
    }
    // The path tracer's light bounces off the studio; a rasteriser has only direct light.
    // Stand in for one bounce with an ambient term: the backdrop's radiance under the lights'
    // irradiance at the garment, scaled by the share of it that reaches the garment (0.2, matched by eye to renders
    // of the default scene).
    const Bounds garment_bounds = bounds(geometry.garment.positions);
    const Vec3f centre = 0.5f * (garment_bounds.min + garment_bounds.max);
    Vec3f irradiance = Vec3f::Zero();
    for (const AreaLight& l : lit_scene.lights) {
        const Vec3f intensity = l.radiance * (l.width_m * l.height_m);
        p.lights.push_back({l.position, intensity, std::max(l.width_m, l.height_m)});
        irradiance += intensity / std::max((l.position - centre).squaredNorm(), 1e-6f);
    }
    const Vec3f bounce = lit_scene.backdrop == SceneSpec::Backdrop::none
                             ? Vec3f::Zero()
                             : Vec3f(0.2f * lit_scene.backdrop_colour.cwiseProduct(irradiance) / kPiF);
    p.camera.position = camera.position;
    p.camera.target = camera.target;
    p.camera.up = camera.up;
    p.camera.vertical_fov_deg = static_cast<float>(camera.fov_deg);
    p.ambient = lit_scene.environment + bounce;
    p.background = lit_scene.environment;
    p.transparent_background = lit_scene.transparent;
    return p;
}

RenderResult preview_frame(PreviewRenderer& renderer, const SceneSpec& lit_scene, const FrameGeometry& geometry,
                           const Camera& camera, const std::vector<Aov>& aovs) {
    const std::vector<Mesh> studio = studio_meshes(geometry);
    PreviewScene scene = make_preview_scene(lit_scene, geometry, studio, camera);
    scene.want_depth = std::find(aovs.begin(), aovs.end(), Aov::depth) != aovs.end();
    const PreviewImage image = renderer.render(scene);
    RenderResult result;
    result.beauty.width = image.width;
    result.beauty.height = image.height;
    result.beauty.channels = 4;
    result.beauty.pixels = image.rgba;
    for (Aov aov : aovs) {
        if (aov != Aov::depth)
            throw InputError(std::string("AOV '") + aov_name(aov) + "': previews give only the depth AOV");
        Image depth;
        depth.width = image.width;
        depth.height = image.height;
        depth.channels = 1;
        depth.pixels = image.depth;
        result.aovs.push_back({Aov::depth, std::move(depth)});
    }
    result.stats.width = image.width;
    result.stats.height = image.height;
    result.stats.spp = 1;
    return result;
}

RenderResult preview_still(const SceneSpec& scene, const RenderOptions& options, int msaa_samples) {
    const auto start = std::chrono::steady_clock::now();
    const StudioSetup setup(scene, load_garment(scene));
    const int frame = scene.garment.frame;
    if (frame >= setup.frame_count())
        throw InputError("garment.frame = " + std::to_string(frame) + ": the garment has " +
                         std::to_string(setup.frame_count()) + " frame(s)");
    const int width = options.width > 0 ? options.width : scene.width;
    const int height = options.height > 0 ? options.height : scene.height;
    const Camera camera =
        frame_camera(scene.camera, {setup.framing_points(frame, 0.0)}, static_cast<double>(width) / height);
    PreviewRenderer renderer(width, height, msaa_samples);
    RenderResult result = preview_frame(renderer, setup.lit_scene(), setup.geometry(frame, 0.0), camera, options.aovs);
    result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace foldcast::preview
