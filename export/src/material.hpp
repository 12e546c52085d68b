#pragma once
// A look as a glTF metallic-roughness material with the extensions that carry cloth:
// the weave baked into a colour texture and a tangent-space normal map one repeat of the
// pattern wide (KHR_texture_transform tiles them at the look's physical scale over UVs in
// metres), KHR_materials_sheen, KHR_materials_anisotropy, KHR_materials_specular.
#include <optional>

#include "foldcast/looks/looks.hpp"
#include "glb_builder.hpp"

namespace foldcast::gltf {

struct MaterialRef {
    int index = 0;
    bool needs_tangents = false;  // a normal map or anisotropy: the mesh must carry TANGENT
};

// Adds the material (and its images, textures, sampler) to `glb`.  `has_uvs` false: no
// textures (nothing to map them with) and no anisotropy (no tangent frame).
MaterialRef add_material(GlbBuilder& glb, const std::optional<looks::Look>& look, bool has_uvs, int texture_px);

}  // namespace foldcast::gltf
