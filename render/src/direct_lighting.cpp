#include "direct_lighting.hpp"

#include <cmath>

#include "path_reuse.hpp"

namespace foldcast::render {

std::optional<DirectLight> direct_lighting(const EmbreeScene& scene, const Hit& hit, const LightSample& ls,
                                           const V3& f_cos, float pdf_bsdf, std::uint64_t& rays, PathRecord* record) {
    if (!(f_cos.maxCoeff() > 0.0f)) return std::nullopt;
    const Vec3f origin = offset_origin(hit.p, hit.ng, ls.wi);
    const float tmax = std::isfinite(ls.distance) ? ls.distance * (1.0f - 1e-3f) : kInf;
    const bool blocked = scene.occluded(origin, ls.wi, tmax, rays);
    if (record) record->shadow(origin, ls.wi, tmax, blocked);
    if (blocked) return std::nullopt;
    return DirectLight{f_cos, ls.radiance, power_heuristic(ls.pdf, pdf_bsdf) / ls.pdf};
}

V3 bsdf_light_hit(const EmbreeScene& scene, const LightSampler& lights, const Hit& hit, const LightChoice& choice,
                  const LightSample* drawn, const Vec3f& wi, const V3& f_cos, float pdf, std::uint64_t& rays,
                  PathRecord* record) {
    if (!(pdf > 0.0f) || !(f_cos.maxCoeff() > 0.0f) || wi.dot(hit.ng) <= 0.0f) return V3::Zero();
    const Vec3f origin = offset_origin(hit.p, hit.ng, wi);
    RTCRayHit rh;
    const bool any = scene.intersect(origin, wi, rh, rays);
    if (record) record->hit(origin, wi, any, rh.ray.tfar, rh.hit.geomID);
    const float t_surface = any ? rh.ray.tfar : kInf;
    const LightHit lh = lights.hit(origin, wi, t_surface);
    if (lh.index < 0) return V3::Zero();
    return (f_cos / pdf).cwiseProduct(lights.radiance(lh.index)) *
           bsdf_hit_weight(lights, choice, drawn, hit.p, origin, wi, lh, pdf);
}

}  // namespace foldcast::render
