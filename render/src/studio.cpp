#include "foldcast/render/studio.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include "foldcast/core/math.hpp"

namespace foldcast::render {
namespace {

void add_quad(StudioMesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    m.triangles.push_back({a, b, c});
    m.triangles.push_back({a, c, d});
}

// A capped cylinder from a to b.
void add_cylinder(StudioMesh& m, const Vec3f& a, const Vec3f& b, float radius, int segments = 24) {
    const Vec3f axis = (b - a).normalized();
    const Vec3f helper = std::abs(axis.y()) < 0.9f ? Vec3f::UnitY() : Vec3f::UnitX();
    const Vec3f u = axis.cross(helper).normalized();
    const Vec3f v = axis.cross(u);
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (int i = 0; i < segments; ++i) {
        const float phi = 2.0f * kPiF * static_cast<float>(i) / static_cast<float>(segments);
        const Vec3f n = std::cos(phi) * u + std::sin(phi) * v;
        m.positions.push_back(a + radius * n);
        m.normals.push_back(n);
        m.positions.push_back(b + radius * n);
        m.normals.push_back(n);
    }
    for (int i = 0; i < segments; ++i) {
        const auto j = static_cast<std::uint32_t>((i + 1) % segments);
        const auto ii = static_cast<std::uint32_t>(i);
        add_quad(m, base + 2 * ii, base + 2 * j, base + 2 * j + 1, base + 2 * ii + 1);
    }
    // Caps: flat fans with their own vertices so the normals are sharp.
    for (int end = 0; end < 2; ++end) {
        const Vec3f c = end == 0 ? a : b;
        const Vec3f n = end == 0 ? -axis : axis;
        const auto centre = static_cast<std::uint32_t>(m.positions.size());
        m.positions.push_back(c);
        m.normals.push_back(n);
        for (int i = 0; i < segments; ++i) {
            const float phi = 2.0f * kPiF * static_cast<float>(i) / static_cast<float>(segments);
            m.positions.push_back(c + radius * (std::cos(phi) * u + std::sin(phi) * v));
            m.normals.push_back(n);
        }
        for (int i = 0; i < segments; ++i) {
            const auto p = centre + 1 + static_cast<std::uint32_t>(i);
            const auto q = centre + 1 + static_cast<std::uint32_t>((i + 1) % segments);
            if (end == 0)
                m.triangles.push_back({centre, q, p});
            else
                m.triangles.push_back({centre, p, q});
        }
    }
}

// A box with half extents h along the orthonormal axes ax, ay, az, flat-shaded.
void add_box(StudioMesh& m, const Vec3f& c0, const Vec3f& ax, const Vec3f& ay, const Vec3f& az, const Vec3f& h) {
    Vec3f c[8];
    for (int i = 0; i < 8; ++i)
        c[i] = c0 + ((i & 1) ? h.x() : -h.x()) * ax + ((i & 2) ? h.y() : -h.y()) * ay + ((i & 4) ? h.z() : -h.z()) * az;
    const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 4, 6, 2}, {1, 3, 7, 5}, {2, 6, 7, 3}, {0, 1, 5, 4}};
    for (const auto& f : faces) {
        const Vec3f n = (c[f[1]] - c[f[0]]).cross(c[f[2]] - c[f[0]]).normalized();
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (int k = 0; k < 4; ++k) {
            m.positions.push_back(c[f[k]]);
            m.normals.push_back(n);
        }
        add_quad(m, base, base + 1, base + 2, base + 3);
    }
}

}  // namespace

StudioMesh build_cyclorama(const Vec3f& centre, float radius_m, float bottom_y) {
    StudioMesh m;
    m.material = MaterialId::backdrop;
    const float floor_y = bottom_y - std::max(0.15f, 0.45f * radius_m);
    const float wall_z = centre.z() - radius_m - 1.4f;
    const float cove = 0.6f;  // radius of the curve joining floor and wall
    const float half_width = 6.0f;
    // Profile in (z, y) from the front of the floor, round the cove, up the wall.
    std::vector<std::pair<Eigen::Vector2f, Eigen::Vector2f>> profile;  // point, normal
    profile.push_back({{centre.z() + 6.0f, floor_y}, {0.0f, 1.0f}});
    constexpr int kArc = 24;
    for (int i = 0; i <= kArc; ++i) {
        const float a = 0.5f * kPiF * static_cast<float>(i) / kArc;  // 0: floor, pi/2: wall
        const Eigen::Vector2f c(wall_z + cove, floor_y + cove);
        const Eigen::Vector2f n(std::sin(a), std::cos(a));
        profile.push_back({c - cove * n, n});
    }
    profile.push_back({{wall_z, floor_y + 6.0f}, {1.0f, 0.0f}});
    for (const auto& [p, n] : profile) {
        for (float x : {centre.x() - half_width, centre.x() + half_width}) {
            m.positions.emplace_back(x, p.y(), p.x());
            m.normals.emplace_back(0.0f, n.y(), n.x());
        }
    }
    for (std::uint32_t i = 0; i + 1 < profile.size(); ++i) add_quad(m, 2 * i, 2 * i + 1, 2 * i + 3, 2 * i + 2);
    return m;
}

std::vector<StudioMesh> build_supports(SceneSpec::Supports kind, const std::vector<Vec3f>& supports) {
    std::vector<StudioMesh> out;
    if (kind == SceneSpec::Supports::none || supports.empty()) return out;
    StudioMesh clips;
    clips.material = MaterialId::wood;
    StudioMesh wires;
    wires.material = MaterialId::wire;
    // The line through the supports, horizontal: the rod runs along it, clips face across it.
    Vec3f axis = supports.size() > 1 ? Vec3f(supports.back() - supports.front()) : Vec3f::UnitX();
    axis.y() = 0.0f;
    axis = axis.squaredNorm() > 1e-10f ? axis.normalized() : Vec3f::UnitX();
    const Vec3f across = axis.cross(Vec3f::UnitY());
    constexpr float kClipBelow = 0.035f, kClipAbove = 0.025f;
    for (const Vec3f& s : supports)  // a clothes-peg-like clip pinching the cloth
        add_box(clips, s + Vec3f(0.0f, 0.5f * (kClipAbove - kClipBelow), 0.0f), axis, Vec3f::UnitY(), across,
                Vec3f(0.011f, 0.5f * (kClipAbove + kClipBelow), 0.007f));
    if (kind == SceneSpec::Supports::rod) {
        StudioMesh rod;
        rod.material = MaterialId::metal;
        float top = supports.front().y();
        for (const Vec3f& s : supports) top = std::max(top, s.y());
        const float rod_y = top + 0.09f;
        Vec3f a = supports.front(), b = supports.back();
        a.y() = b.y() = rod_y;
        const float overhang = 0.12f + 0.15f * (b - a).norm();
        add_cylinder(rod, a - overhang * axis, b + overhang * axis, 0.009f);
        for (const Vec3f& s : supports)  // short hooks from the rod to each clip
            add_cylinder(wires, s + Vec3f(0.0f, kClipAbove, 0.0f), Vec3f(s.x(), rod_y, s.z()), 0.0015f, 10);
        // The rod hangs on two wires going up out of frame.
        for (const Vec3f& end : {Vec3f(a - 0.7f * overhang * axis), Vec3f(b + 0.7f * overhang * axis)})
            add_cylinder(wires, end, end + Vec3f(0.0f, 4.0f, 0.0f), 0.0015f, 10);
        out.push_back(std::move(rod));
    } else {
        for (const Vec3f& s : supports)
            add_cylinder(wires, s + Vec3f(0.0f, kClipAbove, 0.0f), s + Vec3f(0.0f, 4.0f, 0.0f), 0.0012f, 10);
    }
    out.push_back(std::move(clips));
    out.push_back(std::move(wires));
    return out;
}

std::vector<AreaLight> studio_lights(const Vec3f& centre, double size_m) {
    const float s = static_cast<float>(std::max(0.2, size_m));
    std::vector<AreaLight> lights;
    // Key: a large softbox high on the camera's left.
    lights.push_back(
        {"key", centre + s * Vec3f(-1.6f, 1.3f, 2.0f), centre, 1.2f * s, 1.2f * s, Vec3f(10.4f, 10.0f, 9.4f)});
    // Fill: a wider, dimmer box low on the right, so shadows stay open.
    lights.push_back(
        {"fill", centre + s * Vec3f(2.2f, 0.2f, 2.2f), centre, 1.6f * s, 1.6f * s, Vec3f(2.3f, 2.4f, 2.6f)});
    // Rim: a strip behind and above, to separate the cloth's edges from the wall.
    lights.push_back({"rim", centre + s * Vec3f(0.9f, 1.6f, -0.7f), centre + Vec3f(0.0f, 0.2f * s, 0.0f), 0.3f * s,
                      1.2f * s, Vec3f(16.0f, 16.0f, 16.0f)});
    return lights;
}

}  // namespace foldcast::render
