#include "material.hpp"

#include <algorithm>
#include <cmath>

#include "weave_bake.hpp"

namespace foldcast::gltf {

namespace {
constexpr int kLinear = 9729, kLinearMipmapLinear = 9987, kRepeat = 10497;

nlohmann::json rgb(const Eigen::Vector3f& c) {
    return {std::clamp(c.x(), 0.0f, 1.0f), std::clamp(c.y(), 0.0f, 1.0f), std::clamp(c.z(), 0.0f, 1.0f)};
}

// glTF's anisotropy keeps the roughness across the direction and raises the one along it
// (alpha_t = mix(alpha, 1, strength^2)); foldcast's keeps their geometric mean and stretches
// by 1 / (1 - 0.9 anisotropy).  The strength that gives the same ratio of the two alphas.
double anisotropy_strength(double roughness, double anisotropy) {
    const double alpha = std::max(1e-3, roughness * roughness);
    const double ratio = 1.0 / (1.0 - 0.9 * std::clamp(anisotropy, 0.0, 0.99));
    if (alpha >= 1.0) return 0.0;
    return std::sqrt(std::clamp((ratio * alpha - alpha) / (1.0 - alpha), 0.0, 1.0));
}

int add_png(GlbBuilder& glb, const std::string& bytes, int sampler, const std::string& name) {
    const int view = glb.add_view(bytes, 0);
    const int image = glb.add("images", {{"bufferView", view}, {"mimeType", "image/png"}, {"name", name}});
    return glb.add("textures", {{"source", image}, {"sampler", sampler}});
}

nlohmann::json texture_info(GlbBuilder& glb, int texture, const Eigen::Vector2d& tile_m) {
    glb.use_extension("KHR_texture_transform", false);
    return {{"index", texture},
            {"extensions", {{"KHR_texture_transform", {{"scale", {1.0 / tile_m.x(), 1.0 / tile_m.y()}}}}}}};
}
}  // namespace

MaterialRef add_material(GlbBuilder& glb, const std::optional<looks::Look>& look, bool has_uvs, int texture_px) {
    MaterialRef ref;
    const looks::Appearance a = look ? look->appearance : looks::Appearance{};
    nlohmann::json m = {{"name", look ? look->name : std::string("foldcast default")}, {"doubleSided", true}};
    nlohmann::json pbr = {{"metallicFactor", 0.0}, {"roughnessFactor", std::clamp(a.roughness, 0.0, 1.0)}};
    const bool textured = look && has_uvs && has_pattern(a);
    if (textured) {
        const BakedWeave baked = bake_weave(a, texture_px);
        const int sampler = glb.add(
            "samplers",
            {{"magFilter", kLinear}, {"minFilter", kLinearMipmapLinear}, {"wrapS", kRepeat}, {"wrapT", kRepeat}});
        pbr["baseColorTexture"] = texture_info(
            glb, add_png(glb, baked.colour_png, sampler, a.weave == looks::Weave::none ? "texture" : "weave colour"),
            baked.tile_m);
        m["normalTexture"] = texture_info(glb, add_png(glb, baked.normal_png, sampler, "weave normals"), baked.tile_m);
        ref.needs_tangents = true;
        if (a.anisotropy > 0.0) {
            nlohmann::json aniso = {
                {"anisotropyStrength", anisotropy_strength(a.roughness, a.anisotropy)},
                {"anisotropyTexture",
                 texture_info(glb, add_png(glb, baked.anisotropy_png, sampler, "yarn direction"), baked.tile_m)}};
            m["extensions"]["KHR_materials_anisotropy"] = aniso;
            glb.use_extension("KHR_materials_anisotropy", false);
        }
    } else {
        pbr["baseColorFactor"] = {std::clamp(a.base_colour.x(), 0.0f, 1.0f), std::clamp(a.base_colour.y(), 0.0f, 1.0f),
                                  std::clamp(a.base_colour.z(), 0.0f, 1.0f), 1.0f};
        if (look && has_uvs && a.anisotropy > 0.0) {
            const double rotation =
                a.anisotropy_axis == looks::AnisotropyAxis::weft ? 0.5 * 3.14159265358979323846 : 0.0;
            m["extensions"]["KHR_materials_anisotropy"] = {
                {"anisotropyStrength", anisotropy_strength(a.roughness, a.anisotropy)},
                {"anisotropyRotation", rotation}};
            glb.use_extension("KHR_materials_anisotropy", false);
            ref.needs_tangents = true;
        }
    }
    m["pbrMetallicRoughness"] = pbr;
    if (look && a.sheen_colour.maxCoeff() > 0.0f) {
        m["extensions"]["KHR_materials_sheen"] = {{"sheenColorFactor", rgb(a.sheen_colour)},
                                                  {"sheenRoughnessFactor", std::clamp(a.sheen_roughness, 0.0, 1.0)}};
        glb.use_extension("KHR_materials_sheen", false);
    }
    if (look) {
        // foldcast's F0 is 0.08 x specular; glTF's is 0.04 x specularColor for ior 1.5.
        const double f0_scale = 2.0 * a.specular;
        m["extensions"]["KHR_materials_specular"] = {{"specularColorFactor", {f0_scale, f0_scale, f0_scale}}};
        glb.use_extension("KHR_materials_specular", false);
    }
    ref.index = glb.add("materials", std::move(m));
    return ref;
}

}  // namespace foldcast::gltf
