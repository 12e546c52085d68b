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

inline float power_heuristic(float a, float b) { return a * a / (a * a + b * b); }

// An unoccluded light sample's estimate, f_cos * radiance * weight_over_pdf.
struct DirectLight {
    V3 f_cos;
    V3 radiance;
    float weight_over_pdf = 0.0f;
};

// `drawn` is set to the light sample drawn (left as it is when none was), for the MIS pdf
// of a BSDF-sampled ray that reaches the same light.
std::optional<DirectLight> direct_lighting(const EmbreeScene& scene, const LightSampler& lights,
                                           const LightChoice& choice, const Hit& hit, const Frame& frame,
                                           const ClothBsdf& bsdf, float u_pick, float u_b, std::uint64_t& rays,
                                           LightSample* drawn);

}  // namespace foldcast::render
