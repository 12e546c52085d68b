#pragma once
// What the garment's look puts on the surface at one point: the texture hook.  Image
// textures and normal maps tile every repeat_mm of cloth; procedural weaves come from
// looks::sample_weave, band-limited by the pixel footprint.
#include <memory>

#include "cloth_bsdf.hpp"
#include "foldcast/looks/looks.hpp"

namespace foldcast::render {

struct GarmentSurface {
    BsdfParams bsdf;
    V3 normal_ts{0.0f, 0.0f, 1.0f};  // tangent space: x along warp (u), y along weft (v)
    bool anisotropy_along_weft = false;
};

class GarmentShader {
public:
    // Loads the look's texture and normal map (InputError naming the file if unreadable).
    explicit GarmentShader(const looks::Appearance& appearance);
    ~GarmentShader();
    GarmentShader(const GarmentShader&) = delete;
    GarmentShader& operator=(const GarmentShader&) = delete;

    // uv_m: cloth coordinates in metres; footprint_m: cloth width one pixel covers.
    GarmentSurface shade(const Eigen::Vector2f& uv_m, float footprint_m) const;
    // The look's BSDF parameters other than the diffuse colour: the same at every point
    // (shade() starts from them), so the lobes can be set up once.
    const BsdfParams& lobe_params() const { return lobe_params_; }

private:
    struct Images;
    looks::Appearance appearance_;
    BsdfParams lobe_params_;  // made once: shade() copies them at every hit
    std::unique_ptr<Images> images_;
};

}  // namespace foldcast::render
