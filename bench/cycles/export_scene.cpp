// bench_cycles_export: writes a foldcast scene as JSON for bench/cycles/render_cycles.py, so
// Blender's Cycles renders the same studio: the garment and studio meshes (triangles and
// vertex normals, per material), the resolved area lights, the environment, the camera and
// each material's BSDF parameters (the garment's look averaged over its weave, as the EGL
// preview does: Cycles has no foldcast weave).
//   bench_cycles_export SCENE.toml WIDTH HEIGHT OUT.json
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "foldcast/render/render.hpp"
#include "garment_surface.hpp"
#include "foldcast/render/studio_setup.hpp"

using namespace foldcast;
using namespace foldcast::render;
using nlohmann::json;

namespace {

json vec(const Vec3f& v) { return json::array({v.x(), v.y(), v.z()}); }

json bsdf(const BsdfParams& p) {
    return {
        {"diffuse", vec(p.diffuse)}, {"sheen", vec(p.sheen)},     {"sheen_roughness", p.sheen_roughness}, {"f0", p.f0},
        {"roughness", p.roughness},  {"anisotropy", p.anisotropy}};
}

json mesh(const std::vector<Vec3f>& positions, const std::vector<Vec3f>& normals,
          const std::vector<Triangle>& triangles, const char* material) {
    json m = {
        {"material", material}, {"positions", json::array()}, {"normals", json::array()}, {"triangles", json::array()}};
    for (const Vec3f& p : positions) m["positions"].push_back(vec(p));
    for (const Vec3f& n : normals) m["normals"].push_back(vec(n));
    for (const Triangle& t : triangles) m["triangles"].push_back({t[0], t[1], t[2]});
    return m;
}

const char* material_name(MaterialId id) {
    switch (id) {
        case MaterialId::garment:
            return "garment";
        case MaterialId::backdrop:
            return "backdrop";
        case MaterialId::metal:
            return "metal";
        case MaterialId::wood:
            return "wood";
        case MaterialId::wire:
            return "wire";
    }
    return "backdrop";
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 5) {
        std::fprintf(stderr, "usage: %s SCENE.toml WIDTH HEIGHT OUT.json\n", argv[0]);
        return 2;
    }
    const SceneSpec spec = load_scene(argv[1]);
    const int width = std::stoi(argv[2]), height = std::stoi(argv[3]);
    const StudioSetup setup(spec, load_garment(spec));
    const SceneSpec& scene = setup.lit_scene();
    const int frame = scene.garment.frame;
    const Camera camera =
        frame_camera(scene.camera, {setup.framing_points(frame, 0.0)}, static_cast<double>(width) / height);
    FrameGeometry geometry = setup.geometry(frame, 0.0);
    if (geometry.garment.normals.empty())
        geometry.garment.normals = vertex_normals(geometry.garment.positions, geometry.garment.topology.triangles);

    json out;
    out["width"] = width;
    out["height"] = height;
    out["max_depth"] = scene.max_depth;
    out["camera"] = {{"position", vec(camera.position)},
                     {"target", vec(camera.target)},
                     {"up", vec(camera.up)},
                     {"fov_deg", camera.fov_deg}};
    out["environment"] = vec(scene.environment);
    for (const AreaLight& l : scene.lights)
        out["lights"].push_back({{"position", vec(l.position)},
                                 {"target", vec(l.target)},
                                 {"width_m", l.width_m},
                                 {"height_m", l.height_m},
                                 {"radiance", vec(l.radiance)}});
    out["meshes"].push_back(
        mesh(geometry.garment.positions, geometry.garment.normals, geometry.garment.topology.triangles, "garment"));
    for (const StudioMesh& s : geometry.studio)
        out["meshes"].push_back(mesh(s.positions, s.normals, s.triangles, material_name(s.material)));
    // The materials the tracer uses (render/src/shading.cpp), the garment averaged over a
    // 1 m footprint.
    const GarmentShader shader(scene.look.appearance);
    BsdfParams backdrop;
    backdrop.diffuse = scene.backdrop_colour;
    backdrop.f0 = 0.02f;
    backdrop.roughness = 0.9f;
    out["materials"] = {{"garment", bsdf(shader.shade(Vec2f(0.1f, 0.1f), 1.0f).bsdf)},
                        {"backdrop", bsdf(backdrop)},
                        {"metal", bsdf({V3::Constant(0.02f), V3::Zero(), 0.5f, 0.7f, 0.3f, 0.6f})},
                        {"wood", bsdf({V3(0.60f, 0.43f, 0.27f), V3::Zero(), 0.5f, 0.04f, 0.55f, 0.0f})},
                        {"wire", bsdf({V3::Constant(0.03f), V3::Zero(), 0.5f, 0.5f, 0.35f, 0.0f})}};
    std::ofstream(argv[4]) << out.dump();
    return 0;
}
