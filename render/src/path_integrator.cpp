#include "path_integrator.hpp"

#include <algorithm>

#include "foldcast/core/colour.hpp"

#include "direct_lighting.hpp"
#include "path_reuse.hpp"

namespace foldcast::render {
namespace {

constexpr float kIndirectClamp = 20.0f;  // caps rare caustic fireflies off the metal rod

// BSDF directions a camera ray's first hit on the studio's metal (the rod) takes for the
// light its lobe reflects.  The rod's highlight is the image's noisiest light: its lobe and a
// softbox are about the same size, so whether a BSDF sample lands on the box decides much of
// a sample's value, and at 16 spp that hit-or-miss was most of the denoised rod's error
// (default scene, 320x180, seeds 1-3: the rod's squared error 5.92 x1e-6, 3.26 with the
// first hit's light made noise-free, 3.40 with only its BSDF half made so).  The extra
// directions are one more ray each; the path goes on along the first, whose light hit then
// counts for its share; the camera sample count is unchanged.  docs/benchmarks.md.
constexpr int kMetalBsdfDirections = 4;

void add(V3& radiance, const V3& contribution, int depth) {
    if (!contribution.allFinite()) return;
    if (depth >= 2) {
        const float m = contribution.maxCoeff();
        if (m > kIndirectClamp) {
            radiance += contribution * (kIndirectClamp / m);
            return;
        }
    }
    radiance += contribution;
}

// What the previous vertex left for weighing the light that the path's next ray finds.
struct PreviousVertex {
    float bsdf_pdf = 0.0f;
    bool specular_only = true;  // camera ray: lights are not seen directly
    LightChoice choice;
    LightSample drawn;  // the light sample drawn at the previous vertex (light -1: none)
    Vec3f n = Vec3f::UnitY(), p = Vec3f::Zero();
};

// A light the ray (o, d) hits before t_surface (never for the camera ray) ends the path: its
// light added with its MIS weight; true when one did.
bool add_light_hit(const LightSampler& lights, const PreviousVertex& prev, const Vec3f& o, const Vec3f& d,
                   float t_surface, int depth, float light_hit_share, const V3& beta, V3& radiance) {
    if (depth == 0 || lights.empty()) return false;
    const LightHit lh = lights.hit(o, d, t_surface);
    if (lh.index < 0) return false;
    float w =
        prev.specular_only ? 1.0f : bsdf_hit_weight(lights, prev.choice, &prev.drawn, prev.p, o, d, lh, prev.bsdf_pdf);
    if (depth == 1) w *= light_hit_share;
    add(radiance, beta.cwiseProduct(lights.radiance(lh.index)) * w, depth);
    return true;
}

// A ray that hits nothing sees the environment (the camera's: the background).
void add_environment(const LightSampler& lights, const PreviousVertex& prev, const Vec3f& d, int depth,
                     bool transparent, const V3& beta, PathSample& out) {
    if (depth == 0) {
        out.foreground = !transparent;
        out.radiance = lights.environment();
        return;
    }
    const float pdf_env = lights.environment_pdf(prev.choice, d, prev.n);
    const float w = power_heuristic(prev.bsdf_pdf, pdf_env);
    add(out.radiance, beta.cwiseProduct(lights.environment()) * w, depth);
}

// The camera ray's first hit, for the AOVs and the denoiser's features.
void keep_first_hit(PathSample& out, const Hit& hit, const ClothBsdf& bsdf, const Frame& frame, bool transparent) {
    out.albedo = bsdf.albedo();
    out.normal = hit.ns;
    out.shading_normal = frame.n;
    out.depth = hit.t;
    out.garment = hit.material == MaterialId::garment;
    out.turning = hit.material != MaterialId::backdrop;
    out.metal = hit.material == MaterialId::metal || hit.material == MaterialId::wire;
    out.fold = out.garment ? hit.fold : 0.0f;
    if (transparent && hit.material == MaterialId::backdrop) out.foreground = false;
}

}  // namespace

PathSample PathIntegrator::trace(const Vec3f& cam_o, const Vec3f& cam_d, bool first_hit, const RTCRay& ray0,
                                 const RTCHit& hit0, float pixel_angle, PixelSampler& sampler, std::uint64_t& rays,
                                 PathRecord* record) const {
    PathSample out;
    V3 beta = V3::Ones();
    Vec3f o = cam_o, d = cam_d;
    bool have_hit = first_hit;
    RTCRay cur_ray = ray0;
    RTCHit cur_hit = hit0;
    RTCRayHit rh;
    PreviousVertex prev;
    float cone = 0.0f, spread = pixel_angle;
    float light_hit_share = 1.0f;  // of the light the first hit's BSDF sample reaches (split at metal)
    if (record) record->hit(cam_o, cam_d, first_hit, ray0.tfar, hit0.geomID);
    for (int depth = 0;; ++depth) {
        // Emission seen along the ray: lights (not for camera rays) and the environment.
        const float t_surface = have_hit ? cur_ray.tfar : kInf;
        if (add_light_hit(lights_, prev, o, d, t_surface, depth, light_hit_share, beta, out.radiance)) break;
        if (!have_hit) {
            add_environment(lights_, prev, d, depth, transparent_, beta, out);
            break;
        }
        // The last vertex of a path past the camera's shades nothing: its emission was taken
        // above, and it neither samples a light nor continues (the camera's keeps its AOVs).
        if (depth > 0 && depth + 1 >= max_depth_) break;
        Hit hit = scene_.surface(cur_ray, cur_hit);
        cone += hit.t * spread;
        const Vec3f wo = -d;
        Frame frame;  // every material sets it (after orienting the normals towards wo)
        const float cos_view = std::max(0.2f, std::abs(wo.dot(hit.ng)));
        const BsdfLobes* lobes = nullptr;  // set with the frame
        const BsdfParams params = materials_.at(hit, wo, cone / cos_view, &frame, &lobes);
        const ClothBsdf bsdf(params, *lobes, frame.to_local(wo));
        if (depth == 0) keep_first_hit(out, hit, bsdf, frame, transparent_);
        if (depth + 1 >= max_depth_) break;

        // Next-event estimation's light sample and the BSDF sample that continues the path,
        // both drawn first (the sampler's dimensions in the same order as before) so that the
        // BSDF is evaluated at the two directions together (eval2).
        LightChoice choice = lights_.choose(hit.p, hit.ns);
        // The studio's metal (rod, clips, wires) reflects the softboxes in a narrow lobe:
        // choosing a light by what it sends the surface alone leaves most of a highlight's
        // light samples on lights the lobe does not see (default scene, 640x360, 16 spp: the
        // rod's squared error 40.7 -> 23.2 plain, 7.4 -> 4.2 denoised; docs/benchmarks.md).
        if (hit.material == MaterialId::metal) {
            lights_.weight_for_glossy(choice, hit.p, reflect(wo, frame.n), [&](const Vec3f& wi) {
                float pdf = 0.0f;
                return luminance(bsdf.eval(frame.to_local(wi), &pdf));
            });
        }
        const Eigen::Vector2f u_light = sampler.get2d();  // the light's choice and the point on it
        const std::optional<LightSample> ls =
            lights_.sample(choice, hit.p, hit.ns, hit.tangent, u_light.x(), u_light.y());
        const bool light_above = ls && ls->wi.dot(hit.ng) > 0.0f;
        const float u_lobe = sampler.get1d();
        const Eigen::Vector2f u_dir = sampler.get2d();
        // At a split vertex every direction, the path's own too, comes from the split samples,
        // so that the pixel's 16 x 4 directions are stratified together.
        const int directions = depth == 0 && hit.material == MaterialId::metal ? kMetalBsdfDirections : 1;
        auto split_direction = [&](int k) {
            PixelSampler split = sampler.split(static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(directions));
            const float u = split.get1d();
            const Eigen::Vector2f uv = split.get2d();
            return bsdf.sample_direction(u, uv.x(), uv.y());
        };
        const std::optional<V3> wi_local =
            directions > 1 ? split_direction(0) : bsdf.sample_direction(u_lobe, u_dir.x(), u_dir.y());
        V3 f_light = V3::Zero(), f_bsdf = V3::Zero();
        float pdf_light = 0.0f, pdf_bsdf = 0.0f;
        if (light_above && wi_local)
            bsdf.eval2(frame.to_local(ls->wi), *wi_local, &f_light, &pdf_light, &f_bsdf, &pdf_bsdf);
        else if (light_above)
            f_light = bsdf.eval(frame.to_local(ls->wi), &pdf_light);
        else if (wi_local)
            f_bsdf = bsdf.eval(*wi_local, &pdf_bsdf);
        if (light_above)
            if (const auto direct = direct_lighting(scene_, hit, *ls, f_light, pdf_light, rays, record))
                add(out.radiance,
                    beta.cwiseProduct(direct->f_cos).cwiseProduct(direct->radiance) * direct->weight_over_pdf,
                    depth + 1);

        if (directions > 1) {
            light_hit_share = 1.0f / static_cast<float>(directions);
            V3 more = V3::Zero();
            for (int k = 1; k < directions; ++k)
                if (const std::optional<V3> wk = split_direction(k)) {
                    float pdf_k = 0.0f;
                    const V3 f_k = bsdf.eval(*wk, &pdf_k);
                    more += bsdf_light_hit(scene_, lights_, hit, choice, ls ? &*ls : nullptr, frame.to_world(*wk), f_k,
                                           pdf_k, rays, record);
                }
            add(out.radiance, beta.cwiseProduct(more) * light_hit_share, depth + 1);
        }

        // Continue the path along the BSDF sample.
        if (!wi_local || !(pdf_bsdf > 0.0f)) break;
        const V3 weight = f_bsdf / pdf_bsdf;  // f cos / pdf
        const Vec3f wi = frame.to_world(*wi_local);
        if (wi.dot(hit.ng) <= 0.0f) break;
        beta = beta.cwiseProduct(weight);
        if (depth >= 2) {  // Russian roulette
            const float q = std::min(0.95f, beta.maxCoeff());
            if (sampler.get1d() >= q) break;
            beta /= q;
        }
        prev = PreviousVertex{pdf_bsdf, false, choice, ls.value_or(LightSample{}), hit.ns, hit.p};
        spread += 0.2f;  // a rough bounce widens the footprint cone
        o = offset_origin(hit.p, hit.ng, wi);
        d = wi;
        have_hit = scene_.intersect(o, d, rh, rays);
        if (record) record->hit(o, d, have_hit, rh.ray.tfar, rh.hit.geomID);
        cur_ray = rh.ray;
        cur_hit = rh.hit;
    }
    return out;
}

}  // namespace foldcast::render
