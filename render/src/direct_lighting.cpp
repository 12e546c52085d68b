#include "direct_lighting.hpp"

#include <cmath>

namespace foldcast::render {

std::optional<DirectLight> direct_lighting(const EmbreeScene& scene, const LightSampler& lights,
                                           const LightChoice& choice, const Hit& hit, const Frame& frame,
                                           const ClothBsdf& bsdf, float u_pick, float u_b, std::uint64_t& rays,
                                           LightSample* drawn) {
    const std::optional<LightSample> ls = lights.sample(choice, hit.p, hit.ns, hit.tangent, u_pick, u_b);
    if (ls) *drawn = *ls;
    if (!ls || ls->wi.dot(hit.ng) <= 0.0f) return std::nullopt;
    float pdf_bsdf = 0.0f;
    const V3 fc = bsdf.eval(frame.to_local(ls->wi), &pdf_bsdf);
    if (!(fc.maxCoeff() > 0.0f)) return std::nullopt;
    const Vec3f origin = offset_origin(hit.p, hit.ng, ls->wi);
    const float tmax = std::isfinite(ls->distance) ? ls->distance * (1.0f - 1e-3f) : kInf;
    if (scene.occluded(origin, ls->wi, tmax, rays)) return std::nullopt;
    return DirectLight{fc, ls->radiance, power_heuristic(ls->pdf, pdf_bsdf) / ls->pdf};
}

}  // namespace foldcast::render
