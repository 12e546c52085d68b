#include "shading.hpp"

#include <stdexcept>

namespace foldcast::render {

Materials::Materials(const SceneSpec& scene) : garment_(std::make_unique<GarmentShader>(scene.look.appearance)) {
    backdrop_.diffuse = scene.backdrop_colour;
    backdrop_.f0 = 0.02f;
    backdrop_.roughness = 0.9f;
    metal_ = {V3::Constant(0.02f), V3::Zero(), 0.5f, 0.7f, 0.3f, 0.6f};
    wood_ = {V3(0.60f, 0.43f, 0.27f), V3::Zero(), 0.5f, 0.04f, 0.55f, 0.0f};
    wire_ = {V3::Constant(0.03f), V3::Zero(), 0.5f, 0.5f, 0.35f, 0.0f};
    garment_lobes_ = BsdfLobes(garment_->lobe_params());
    backdrop_lobes_ = BsdfLobes(backdrop_);
    metal_lobes_ = BsdfLobes(metal_);
    wood_lobes_ = BsdfLobes(wood_);
    wire_lobes_ = BsdfLobes(wire_);
}

BsdfParams Materials::at(Hit& hit, const Vec3f& wo, float footprint_m, Frame* frame, const BsdfLobes** lobes) const {
    if (hit.ng.dot(wo) < 0.0f) {
        hit.ng = -hit.ng;
        hit.ns = -hit.ns;
    }
    if (hit.ns.dot(wo) <= 1e-4f) hit.ns = hit.ng;  // shading normal facing away: fall back
    switch (hit.material) {
        case MaterialId::garment: {
            const GarmentSurface s = garment_->shade(hit.uv, footprint_m);
            const Frame base(hit.ns, hit.tangent);
            Vec3f n = normalized3(base.to_world(s.normal_ts));
            if (n.dot(wo) <= 1e-4f) n = hit.ns;
            *frame = Frame(n, s.anisotropy_along_weft ? base.b : base.t);
            *lobes = &garment_lobes_;
            return s.bsdf;
        }
        case MaterialId::backdrop:
            *frame = Frame(hit.ns, hit.tangent);
            *lobes = &backdrop_lobes_;
            return backdrop_;
        case MaterialId::metal:
            *frame = Frame(hit.ns, Vec3f::UnitX());
            *lobes = &metal_lobes_;
            return metal_;
        case MaterialId::wood:
            *frame = Frame(hit.ns, Vec3f::UnitY());
            *lobes = &wood_lobes_;
            return wood_;
        case MaterialId::wire:
            *frame = Frame(hit.ns, Vec3f::UnitY());
            *lobes = &wire_lobes_;
            return wire_;
    }
    throw std::logic_error("unknown material");
}

}  // namespace foldcast::render
