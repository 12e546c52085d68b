#pragma once
// The studio around the garment: a cyclorama (floor curving up into a back wall), the rod
// or clips at the supports, and the key/fill/rim light preset.
#include <vector>

#include "foldcast/render/render.hpp"

namespace foldcast::render {

enum class MaterialId : unsigned { garment = 0, backdrop, metal, wood, wire };

struct StudioMesh {
    std::vector<Vec3f> positions;
    std::vector<Vec3f> normals;  // per vertex
    std::vector<Triangle> triangles;
    MaterialId material = MaterialId::backdrop;
};

// A cyclorama below and behind a garment whose points lie within `radius_m` of the vertical
// axis through `centre` and above `bottom_y`.
StudioMesh build_cyclorama(const Vec3f& centre, float radius_m, float bottom_y);

// Hardware at the supports: for Supports::rod a metal rod just above the supports with the
// clips hanging from it, for Supports::clips wooden clips on wires going up out of frame.
std::vector<StudioMesh> build_supports(SceneSpec::Supports kind, const std::vector<Vec3f>& supports);

}  // namespace foldcast::render
