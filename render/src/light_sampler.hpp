#pragma once
// Light selection for next-event estimation: the scene's one-sided rectangular area lights
// and the uniform environment, one of them picked per path vertex in proportion to its
// expected unoccluded contribution there, and the pdfs MIS needs when a BSDF-sampled ray
// reaches a light or the sky instead.
#include <array>
#include <optional>
#include <vector>

#include "cloth_bsdf.hpp"
#include "foldcast/render/render.hpp"

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
    // The same choice re-weighted for a glossy surface at p, whose lobe peaks about the
    // mirror direction `mirror`: each light's share in proportion to its choice probability
    // times `lobe(wi)` (the BSDF's luminance times cosine towards wi), taken towards the
    // light's point nearest to where the mirror ray meets its plane, mixed with the plain
    // choice by kGlossyChoiceMix.  Unchanged when the lobe sees none of the lights there.
    template <class Lobe>
    void weight_for_glossy(LightChoice& choice, const Vec3f& p, const Vec3f& mirror, Lobe&& lobe) const;
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
    // Light `index`'s point nearest to where the ray p + t d (t > 0) meets its plane; its
    // centre when the ray does not meet it.
    Vec3f point_towards(int index, const Vec3f& p, const Vec3f& d) const;

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

// The share of a glossy vertex's light choice that follows its lobe: the rest keeps the plain
// choice, so that a light the lobe's estimate misses (a softbox whose reflection lies beside
// the point taken) is still sampled.
constexpr float kGlossyChoiceMix = 0.9f;

template <class Lobe>
void LightSampler::weight_for_glossy(LightChoice& choice, const Vec3f& p, const Vec3f& mirror, Lobe&& lobe) const {
    const int count = this->count();
    std::array<float, kMaxLights> towards{};
    float lobe_sum = 0.0f, area_sum = 0.0f;
    for (int i = 0; i < count; ++i) {
        if (!(choice.prob[i] > 0.0f)) continue;
        towards[i] = choice.prob[i] * lobe((point_towards(i, p, mirror) - p).normalized());
        lobe_sum += towards[i];
        area_sum += choice.prob[i];
    }
    if (!(lobe_sum > 0.0f)) return;
    // The area lights keep their total share (the environment's is not changed).
    const float scale = kGlossyChoiceMix * area_sum / lobe_sum;
    for (int i = 0; i < count; ++i) choice.prob[i] = (1.0f - kGlossyChoiceMix) * choice.prob[i] + scale * towards[i];
}

}  // namespace foldcast::render
