#include "tangents.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace foldcast::gltf {

std::vector<Eigen::Vector4f> vertex_tangents(const std::vector<Vec3f>& positions, const std::vector<Vec3f>& normals,
                                             const Topology& topology) {
    const std::size_t n = positions.size();
    std::vector<Vec3f> along_u(n, Vec3f::Zero()), along_v(n, Vec3f::Zero());
    for (const Triangle& t : topology.triangles) {
        const Vec3f e1 = positions[t[1]] - positions[t[0]], e2 = positions[t[2]] - positions[t[0]];
        const Vec2f d1 = topology.uvs[t[1]] - topology.uvs[t[0]], d2 = topology.uvs[t[2]] - topology.uvs[t[0]];
        const float det = d1.x() * d2.y() - d2.x() * d1.y();
        if (!(std::abs(det) > 0.0f)) continue;
        // dP/du and dP/dv of the triangle, weighted by its UV area (|det| / 2) so that small
        // triangles count less: (e1 d2.y - e2 d1.y) / det * |det|.
        const float sign = det > 0.0f ? 1.0f : -1.0f;
        const Vec3f du = (e1 * d2.y() - e2 * d1.y()) * sign, dv = (e2 * d1.x() - e1 * d2.x()) * sign;
        for (const std::uint32_t i : t) along_u[i] += du, along_v[i] += dv;
    }
    std::vector<Eigen::Vector4f> tangents(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3f& normal = normals[i];
        Vec3f t = along_u[i] - normal * normal.dot(along_u[i]);
        if (!(t.norm() > 1e-12f)) {
            // No UV gradient here: any direction in the tangent plane.
            const Vec3f other = std::abs(normal.x()) < 0.9f ? Vec3f::UnitX() : Vec3f::UnitY();
            t = other - normal * normal.dot(other);
        }
        t.normalize();
        const float w = normal.cross(t).dot(along_v[i]) > 0.0f ? -1.0f : 1.0f;
        tangents[i] = Eigen::Vector4f(t.x(), t.y(), t.z(), w);
    }
    return tangents;
}

}  // namespace foldcast::gltf
