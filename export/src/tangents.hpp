#pragma once
// Per-vertex tangent frames for normal maps and anisotropy: xyz along +u (the warp),
// orthogonal to the normal, w the sign that makes cross(normal, xyz) * w point along -v, as
// glTF's normal maps (+Y towards the image's top) expect.
#include <Eigen/Core>
#include <vector>

#include "foldcast/core/mesh.hpp"

namespace foldcast::gltf {

std::vector<Eigen::Vector4f> vertex_tangents(const std::vector<Vec3f>& positions, const std::vector<Vec3f>& normals,
                                             const Topology& topology);

}  // namespace foldcast::gltf
