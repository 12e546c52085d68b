#pragma once
// Fixed-topology triangle meshes and animations: the currency between drape, codec and
// render.  Positions are float (what files and the renderer use); solvers work in double.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace foldcast {

using Vec2f = Eigen::Vector2f;
using Vec3f = Eigen::Vector3f;
using Triangle = std::array<std::uint32_t, 3>;

// What stays the same over an animation: triangles and per-vertex UVs (empty if none).
// UVs of foldcast's own garments are in metres of cloth, not [0,1].
struct Topology {
    std::vector<Triangle> triangles;
    std::vector<Vec2f> uvs;
};

struct Mesh {
    std::vector<Vec3f> positions;
    Topology topology;
    std::vector<Vec3f> normals;  // per vertex, unit length; empty if not computed
};

// The largest coordinate a mesh may have (metres in foldcast's own files; any unit in an
// imported one): beyond it, products of coordinates overflow float in the ray tracer.
inline constexpr float kMaxCoordinate = 1e6f;

// T frames of N vertex positions sharing one topology.
struct Animation {
    Topology topology;
    std::vector<std::vector<Vec3f>> frames;
    double fps = 30.0;

    std::size_t vertex_count() const { return frames.empty() ? 0 : frames.front().size(); }
    std::size_t frame_count() const { return frames.size(); }
    // One frame as a mesh with area-weighted vertex normals.
    Mesh frame_mesh(std::size_t frame) const;
};

// Area-weighted vertex normals (a vertex in no triangle gets +z).
std::vector<Vec3f> vertex_normals(const std::vector<Vec3f>& positions, const std::vector<Triangle>& triangles);

// Throws InputError (prefixed by `what`) unless every index is in range, every frame has
// the same vertex count, UVs are absent or one per vertex and all positions are finite.
void validate(const Mesh& mesh, const std::string& what);
void validate(const Animation& anim, const std::string& what);

struct Bounds {
    Vec3f min = Vec3f::Constant(0.0f);
    Vec3f max = Vec3f::Constant(0.0f);
    float diagonal() const { return (max - min).norm(); }
};
// Bounds over all positions (of all frames); zero bounds for no positions.
Bounds bounds(const std::vector<Vec3f>& positions);
Bounds bounds(const Animation& anim);

}  // namespace foldcast
