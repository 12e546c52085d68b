#include "foldcast/core/mesh.hpp"

#include <Eigen/Geometry>

#include <cstdio>
#include <string>

#include "foldcast/core/error.hpp"

namespace foldcast {

std::vector<Vec3f> vertex_normals(const std::vector<Vec3f>& positions, const std::vector<Triangle>& triangles) {
    // Accumulate in double: on fine grids the per-triangle cross products are tiny.
    std::vector<Eigen::Vector3d> sum(positions.size(), Eigen::Vector3d::Zero());
    for (const Triangle& t : triangles) {
        const Eigen::Vector3d a = positions[t[0]].cast<double>();
        const Eigen::Vector3d b = positions[t[1]].cast<double>();
        const Eigen::Vector3d c = positions[t[2]].cast<double>();
        const Eigen::Vector3d n = (b - a).cross(c - a);  // length = 2 * area
        for (std::uint32_t v : t) sum[v] += n;
    }
    std::vector<Vec3f> normals(positions.size());
    for (std::size_t i = 0; i < sum.size(); ++i) {
        const double len = sum[i].norm();
        normals[i] = len > 0.0 ? (sum[i] / len).cast<float>() : Vec3f(0.0f, 0.0f, 1.0f);
    }
    return normals;
}

Mesh Animation::frame_mesh(std::size_t frame) const {
    Mesh mesh;
    mesh.positions = frames.at(frame);
    mesh.topology = topology;
    mesh.normals = vertex_normals(mesh.positions, topology.triangles);
    return mesh;
}

namespace {
void validate_topology(const Topology& topo, std::size_t vertex_count, const std::string& what) {
    for (std::size_t i = 0; i < topo.triangles.size(); ++i)
        for (std::uint32_t v : topo.triangles[i])
            if (v >= vertex_count)
                throw InputError(what + ": triangle " + std::to_string(i) + " uses vertex " + std::to_string(v) +
                                 " but there are only " + std::to_string(vertex_count) + " vertices");
    if (!topo.uvs.empty() && topo.uvs.size() != vertex_count)
        throw InputError(what + ": " + std::to_string(topo.uvs.size()) + " UVs for " + std::to_string(vertex_count) +
                         " vertices (need one per vertex or none)");
    for (const Vec2f& uv : topo.uvs)
        if (!uv.allFinite()) throw InputError(what + ": a UV coordinate is not a finite number");
}

// "1e+30", not std::to_string's 31 digits and six decimals.
std::string short_number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
}

void validate_positions(const std::vector<Vec3f>& positions, const std::string& what) {
    for (std::size_t i = 0; i < positions.size(); ++i) {
        if (!positions[i].allFinite())
            throw InputError(what + ": vertex " + std::to_string(i) + " is not a finite position");
        if (positions[i].cwiseAbs().maxCoeff() > kMaxCoordinate)
            throw InputError(what + ": vertex " + std::to_string(i) + " lies " +
                             short_number(positions[i].cwiseAbs().maxCoeff()) +
                             " from the origin on an axis (coordinates must be within +-1e6, docs/inputs.md)");
    }
}
}  // namespace

void validate(const Mesh& mesh, const std::string& what) {
    validate_topology(mesh.topology, mesh.positions.size(), what);
    validate_positions(mesh.positions, what);
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
        throw InputError(what + ": normals do not match the vertex count");
}

void validate(const Animation& anim, const std::string& what) {
    const std::size_t n = anim.vertex_count();
    for (std::size_t f = 0; f < anim.frames.size(); ++f) {
        if (anim.frames[f].size() != n)
            throw InputError(what + ": frame " + std::to_string(f) + " has " + std::to_string(anim.frames[f].size()) +
                             " vertices, frame 0 has " + std::to_string(n));
        validate_positions(anim.frames[f], what + " frame " + std::to_string(f));
    }
    validate_topology(anim.topology, n, what);
    if (!(anim.fps > 0.0)) throw InputError(what + ": fps must be > 0");
}

Bounds bounds(const std::vector<Vec3f>& positions) {
    Bounds b;
    if (positions.empty()) return b;
    b.min = b.max = positions.front();
    for (const Vec3f& p : positions) {
        b.min = b.min.cwiseMin(p);
        b.max = b.max.cwiseMax(p);
    }
    return b;
}

Bounds bounds(const Animation& anim) {
    Bounds b;
    bool first = true;
    for (const auto& frame : anim.frames) {
        if (frame.empty()) continue;
        const Bounds f = bounds(frame);
        if (first) b = f;
        b.min = b.min.cwiseMin(f.min);
        b.max = b.max.cwiseMax(f.max);
        first = false;
    }
    return b;
}

}  // namespace foldcast
