#pragma once
// Next-event estimation at one path vertex: one light (or the sky) picked by the light
// sampler, a shadow ray, and the power-heuristic MIS weight against BSDF sampling.
#include <cstdint>
#include <optional>

#include "cloth_bsdf.hpp"
#include "embree_scene.hpp"
#include "light_sampler.hpp"
#include "shading.hpp"

namespace foldcast::render {

struct PathRecord;

inline float power_heuristic(float a, float b) { return a * a / (a * a + b * b); }

// An unoccluded light sample's estimate, f_cos * radiance * weight_over_pdf.
struct DirectLight {
    V3 f_cos;
    V3 radiance;
    float weight_over_pdf = 0.0f;
};

// The estimate of light sample `ls`, drawn at `hit` towards the light (ls.wi above the
// surface), whose BSDF value f_cos and pdf were evaluated beforehand (with the vertex's BSDF
// sample, ClothBsdf::eval2): nothing when the BSDF is black there or the shadow ray is
// blocked.
// `record`, if any, is told the shadow ray and whether it was blocked.
std::optional<DirectLight> direct_lighting(const EmbreeScene& scene, const Hit& hit, const LightSample& ls,
                                           const V3& f_cos, float pdf_bsdf, std::uint64_t& rays,
                                           PathRecord* record = nullptr);

}  // namespace foldcast::render
