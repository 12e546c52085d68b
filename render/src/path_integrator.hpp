#pragma once
// The path integrator: one camera path from its packet-traced first hit, with next-event
// estimation and MIS at every vertex, Russian roulette from the third, and the first hit's
// albedo, normal, depth and fold sign for the AOVs.
#include <cstdint>

#include "embree_scene.hpp"
#include "light_sampler.hpp"
#include "sobol_sampler.hpp"
#include "shading.hpp"

namespace foldcast::render {

struct PathRecord;

struct PathSample {
    V3 radiance = V3::Zero();
    bool foreground = true;  // false: the camera saw the backdrop or the sky
    bool garment = false;    // the camera ray's first hit is the garment
    bool turning = false;    // ... is the garment or its supports (what a turntable turns)
    bool metal = false;      // ... is the rod or a wire (a highlight that turns fast with the view)
    V3 albedo = V3::Zero();
    Vec3f normal = Vec3f::Zero();          // interpolated (the normal AOV)
    Vec3f shading_normal = Vec3f::Zero();  // with the weave's bump (guides the denoiser)
    float depth = 0.0f;
    float fold = 0.0f;
};

class PathIntegrator {
public:
    PathIntegrator(const EmbreeScene& scene, const LightSampler& lights, const Materials& materials, int max_depth,
                   bool transparent)
        : scene_(scene), lights_(lights), materials_(materials), max_depth_(max_depth), transparent_(transparent) {}

    // `first_hit`: whether the camera ray (ray0, hit0) hit anything; pixel_angle: the
    // camera's cone spread per pixel, for texture footprints.
    PathSample trace(const Vec3f& cam_o, const Vec3f& cam_d, bool first_hit, const RTCRay& ray0, const RTCHit& hit0,
                     float pixel_angle, PixelSampler& sampler, std::uint64_t& rays, PathRecord* record = nullptr) const;

private:
    const EmbreeScene& scene_;
    const LightSampler& lights_;
    const Materials& materials_;
    int max_depth_;
    bool transparent_;
};

}  // namespace foldcast::render
