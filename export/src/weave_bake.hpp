#pragma once
// The look's surface pattern baked into images that tile: the procedural weave (looks'
// sample_weave, the function the path tracer shades with), over the look's texture and
// normal-map images where it has them, combined as render's garment shader combines them.
#include <Eigen/Core>
#include <string>

#include "foldcast/looks/looks.hpp"

namespace foldcast::gltf {

struct BakedWeave {
    Eigen::Vector2d tile_m{0.0, 0.0};  // the images' extent on the cloth (u, v)
    std::string colour_png;            // sRGB base colour
    std::string normal_png;            // tangent-space normals, glTF's convention (+Y = -v)
    std::string anisotropy_png;        // KHR_materials_anisotropy: direction of the yarn on top, strength 1
};

// Whether the look has anything to bake (a weave, a texture or a normal-map image).
bool has_pattern(const looks::Appearance& appearance);
// Images of `px` x `px` covering whole repeats of the weave and of the texture images.
// Throws InputError naming a texture or normal map that cannot be read.
BakedWeave bake_weave(const looks::Appearance& appearance, int px);

}  // namespace foldcast::gltf
