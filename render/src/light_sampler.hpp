#pragma once
// Light selection for next-event estimation: the scene's one-sided rectangular area lights
// and the uniform environment, one of them picked per path vertex in proportion to its
// expected unoccluded contribution there, and the pdfs MIS needs when a BSDF-sampled ray
// reaches a light or the sky instead.
#include <array>
#include <optional>
#include <vector>

#include "cloth_bsdf.hpp"
#include "foldcast/render.hpp"

namespace foldcast::render {

constexpr int kMaxLights = 16;

struct Light {
    Vec3f centre, normal, ex, ey;  // ex, ey: unit axes
    Vec3f corner;                  // centre - half_w ex - half_h ey
    float half_w = 0, half_h = 0, area = 0;
    V3 radiance;
    float power = 0;  // luminance(radiance) * area: the choice's weight before distance and angles
};

// Probabilities of picking each light (and the environment, last) at one path vertex.
struct LightChoice {
    std::array<float, kMaxLights + 1> prob{};
    int options = 0;  // lights + 1
};

struct LightSample {
    Vec3f wi = Vec3f::Zero();  // towards the light
    float distance = 0;  // infinite for the environment
    float pdf = 0;       // solid angle, including the choice probability
    V3 radiance = V3::Zero();
    int light = -1;         // the area light's index; -1 for the environment
    float solid_angle = 0;  // of that light at the sampled point, when sampled in solid angle
};

struct LightHit {
    int index = -1;  // -1: none
    float t = 0.0f;
};

class LightSampler {
public:
    LightSampler(const std::vector<AreaLight>& lights, const V3& environment);

    bool empty() const { return lights_.empty(); }
    int count() const { return static_cast<int>(lights_.size()); }
    const V3& environment() const { return environment_; }

    LightChoice choose(const Vec3f& p, const Vec3f& n) const;
    // Picks by u_pick and samples a point on it, uniformly in the solid angle it subtends at
    // p (uniformly over its area where that is too small to measure), or a cosine direction
    // about `n` for the environment, with (u_a, u_b), u_a being u_pick rescaled within the
    // chosen light's share: one stratified 2-D point (u_pick, u_b) stratifies the choice
    // and the point together.  Nothing when the pick has no probability or the light faces
    // away.
    std::optional<LightSample> sample(const LightChoice& choice, const Vec3f& p, const Vec3f& n, const Vec3f& tangent,
                                      float u_pick, float u_b) const;
    // The nearest light's front face along o + t d, t < tmax.
    LightHit hit(const Vec3f& o, const Vec3f& d, float tmax) const;
    // What sample() at p would have given for the point q on light `index`.  `drawn`: what
    // sample() drew at p, if anything; when it was this light its solid angle is reused
    // rather than the spherical rectangle set up again (the same floats).
    float pdf(const LightChoice& choice, int index, const Vec3f& p, const Vec3f& q,
              const LightSample* drawn = nullptr) const;
    const V3& radiance(int index) const { return lights_[index].radiance; }
    // What sample() would have given for the environment in direction d, with n the normal
    // the choice was made for.
    float environment_pdf(const LightChoice& choice, const Vec3f& d, const Vec3f& n) const;

private:
    std::vector<Light> lights_;
    // What choose() and hit() read of each light, one array per coordinate (lights beyond
    // count() zero), so that they take four lights at once.
    struct Lanes {
        alignas(16) std::array<float, kMaxLights> cx{}, cy{}, cz{}, nx{}, ny{}, nz{}, power{};
        alignas(16) std::array<float, kMaxLights> exx{}, exy{}, exz{}, eyx{}, eyy{}, eyz{}, half_w{}, half_h{};
    } lanes_;
    V3 environment_;
    float environment_power_;  // luminance * pi, the environment's weight in a choice
};

}  // namespace foldcast::render
