#pragma once
// Warping of uniform random numbers in [0,1)^2 to directions, in a local frame with z the
// normal. Shared by the BSDF and the light sampler so that both use the same map and pdf.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "foldcast/core/fast_math.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast {

// Malley's method: uniform on the unit disk lifted to the hemisphere; pdf = cos(theta) / pi.
// The azimuth's sine and cosine from u2 in turns (fast_math.hpp: no libm call).
inline Eigen::Vector3f sample_cosine_hemisphere(float u1, float u2) {
    const float r = std::sqrt(u1);
    const SinCos phi = sincos_turns(u2);
    return {r * phi.cos, r * phi.sin, std::sqrt(std::max(0.0f, 1.0f - u1))};
}
inline float cosine_hemisphere_pdf(float cos_theta) { return cos_theta / kPiF; }

// Uniform over the hemisphere (z = u1); pdf = 1 / (2 pi).
inline Eigen::Vector3f sample_uniform_hemisphere(float u1, float u2) {
    const float z = u1, r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const SinCos phi = sincos_turns(u2);
    return {r * phi.cos, r * phi.sin, z};
}
inline float uniform_hemisphere_pdf() { return 1.0f / (2.0f * kPiF); }

}  // namespace foldcast
