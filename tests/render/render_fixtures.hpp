#pragma once
// Small scenes built in code, fast enough for unit tests.
#include <Eigen/Geometry>
#include <cmath>

#include "test_paths.hpp"
#include "foldcast/core/mesh_io.hpp"
#include "foldcast/render/render.hpp"

namespace foldcast::test {

// A UV sphere of radius r at the origin, written as OBJ.
inline std::filesystem::path write_sphere(const std::filesystem::path& dir, float r, int rings = 64,
                                          int segments = 128) {
    Mesh m;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j <= segments; ++j) {
            const float th = 3.14159265f * static_cast<float>(i) / rings;
            const float ph = 6.2831853f * static_cast<float>(j) / segments;
            m.positions.emplace_back(r * std::sin(th) * std::cos(ph), r * std::cos(th),
                                     r * std::sin(th) * std::sin(ph));
            m.topology.uvs.emplace_back(static_cast<float>(j) / segments, static_cast<float>(i) / rings);
        }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const auto a = static_cast<std::uint32_t>(i * (segments + 1) + j), b = a + 1;
            const auto c = a + static_cast<std::uint32_t>(segments + 1), d = c + 1;
            m.topology.triangles.push_back({a, b, c});
            m.topology.triangles.push_back({b, d, c});
        }
    m.normals = vertex_normals(m.positions, m.topology.triangles);
    const auto path = dir / "sphere.obj";
    write_obj(path, m);
    return path;
}

// A 0.5 x 0.7 m sheet hanging in the x-y plane (top edge at y = 0) with sinusoidal folds,
// UVs in metres, like drape's garments.  Written atomically, so parallel tests may share it.
inline std::filesystem::path hanging_cloth() {
    Mesh m;
    constexpr int nu = 26, nv = 36;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const float u = static_cast<float>(i) / (nu - 1), v = static_cast<float>(j) / (nv - 1);
            const float x = 0.5f * (u - 0.5f), y = -0.7f * v;
            const float z = 0.03f * std::sin(6.2831853f * 3.0f * u) * (0.3f + v);
            m.positions.emplace_back(x, y, z);
            m.topology.uvs.emplace_back(0.5f * u, 0.7f * v);
        }
    for (int j = 0; j + 1 < nv; ++j)
        for (int i = 0; i + 1 < nu; ++i) {
            const auto a = static_cast<std::uint32_t>(j * nu + i), b = a + 1, c = a + nu, d = c + 1;
            m.topology.triangles.push_back({a, c, b});
            m.topology.triangles.push_back({b, c, d});
        }
    const auto dir = std::filesystem::path(FOLDCAST_BINARY_DIR) / "test-tmp";
    std::filesystem::create_directories(dir);
    write_obj(dir / "hanging_cloth.obj", m);
    return dir / "hanging_cloth.obj";
}

// The hanging sheet in a studio: cyclorama, clips, studio lights.
inline render::SceneSpec cloth_scene(int width = 64, int height = 48, int spp = 4) {
    render::SceneSpec s;
    s.garment.source = render::GarmentSpec::Source::obj;
    s.garment.path = hanging_cloth();
    s.look.appearance.base_colour = Vec3f(0.6f, 0.3f, 0.2f);
    s.look.appearance.sheen_colour = Vec3f(0.4f, 0.4f, 0.4f);
    s.look.appearance.weave = looks::Weave::none;
    s.supports = render::SceneSpec::Supports::clips;
    s.width = width;
    s.height = height;
    s.spp = spp;
    return s;
}

}  // namespace foldcast::test
