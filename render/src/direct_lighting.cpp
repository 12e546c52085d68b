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

}  // namespace foldcast::render
