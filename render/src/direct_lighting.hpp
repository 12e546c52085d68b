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

// The MIS weight of a BSDF-sampled ray o + t d, drawn with pdf_bsdf at vertex p, that reaches
// the area light `lh`: against the light sampling that could have drawn the same point there
// (the vertex's light choice, and `drawn`, its light sample, if any).
inline float bsdf_hit_weight(const LightSampler& lights, const LightChoice& choice, const LightSample* drawn,
                             const Vec3f& p, const Vec3f& o, const Vec3f& d, const LightHit& lh, float pdf_bsdf) {
    return power_heuristic(pdf_bsdf, lights.pdf(choice, lh.index, p, o + lh.t * d, drawn));
}

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

// The other half of the vertex's MIS pair for one more BSDF direction wi (world, f_cos and
// pdf its BSDF value and sampling pdf): the radiance of the area light the ray reaches
// first, times f_cos / pdf and the power-heuristic weight against the vertex's light choice
// (`drawn`: its light sample, if any), as the path's own BSDF sample gets it at the next
// vertex.  Zero when the ray meets the scene or the sky first (the sky is left to the path).
// The ray is recorded in `record` (path_reuse.hpp) when there is one.
V3 bsdf_light_hit(const EmbreeScene& scene, const LightSampler& lights, const Hit& hit, const LightChoice& choice,
                  const LightSample* drawn, const Vec3f& wi, const V3& f_cos, float pdf, std::uint64_t& rays,
                  PathRecord* record = nullptr);

}  // namespace foldcast::render
