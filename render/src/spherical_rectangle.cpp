// Urena, Conty and Kulla 2013, section 3, in single precision as pbrt-v4 and Cycles use it:
// the edge planes' normals and the angles between them in closed form from the corner's
// local coordinates.  Single precision loses the small solid angles (the sum of four angles
// minus 2 pi cancels), which is why make() leaves those to area sampling.
#include "spherical_rectangle.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>

#include "foldcast/core/fast_math.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::render {
namespace {

// The angle between two edge planes from the cosine of it: acos by Hastings' polynomial
// (Abramowitz and Stegun 4.4.46, |error| <= 2e-8 rad, below float's rounding at pi), a
// square root and eight multiply-adds where libm's acosf took a tenth of make()'s callers'
// time.  make() takes four at once in SSE2 lanes (interior_angles below), else this.
// The polynomial's coefficients, constant term first; both versions evaluate it by Horner's
// rule from the last, the same operations in the same order.
constexpr float kAcosPolynomial[8] = {1.5707963050f, -0.2145988016f, 0.0889789874f, -0.0501743046f,
                                      0.0308918810f, -0.0170881256f, 0.0066700901f, -0.0012624911f};
#if !defined(__SSE2__)
float interior_angle(float cosine) {
    const float x = std::min(1.0f, std::abs(cosine));
    float p = kAcosPolynomial[7];
    for (int k = 6; k >= 0; --k) p = kAcosPolynomial[k] + x * p;
    const float a = std::sqrt(1.0f - x) * p;
    return cosine < 0.0f ? kPiF - a : a;
}
#else
// interior_angle() of four cosines in the four lanes: the same IEEE operations in the same
// order as the scalar function (no FMA under SSE2), so the same floats, in a quarter of the
// square roots and multiply-adds of four calls (make() was about 5 % of a turntable's CPU).
__m128 interior_angles(__m128 cosine) {
    const __m128 x = _mm_min_ps(_mm_andnot_ps(_mm_set1_ps(-0.0f), cosine), _mm_set1_ps(1.0f));
    __m128 p = _mm_set1_ps(kAcosPolynomial[7]);
    for (int k = 6; k >= 0; --k) p = _mm_add_ps(_mm_set1_ps(kAcosPolynomial[k]), _mm_mul_ps(x, p));
    const __m128 a = _mm_mul_ps(_mm_sqrt_ps(_mm_sub_ps(_mm_set1_ps(1.0f), x)), p);
    const __m128 negative = _mm_cmplt_ps(cosine, _mm_setzero_ps());
    return _mm_or_ps(_mm_and_ps(negative, _mm_sub_ps(_mm_set1_ps(kPiF), a)), _mm_andnot_ps(negative, a));
}
#endif

}  // namespace

std::optional<SphericalRectangle> SphericalRectangle::make(const Vec3f& from, const Vec3f& corner, const Vec3f& ex,
                                                           const Vec3f& ey, float width, float height) {
    SphericalRectangle r;
    r.origin_ = from;
    r.x_ = ex;
    r.y_ = ey;
    r.z_ = ex.cross(ey);
    const Vec3f d = corner - from;
    r.z0_ = d.dot(r.z_);
    if (r.z0_ > 0.0f) {  // the local frame's z points away from the rectangle
        r.z_ = -r.z_;
        r.z0_ = -r.z0_;
    }
    if (!(std::abs(r.z0_) > 1e-6f)) return std::nullopt;
    r.x0_ = d.dot(r.x_);
    r.y0_ = d.dot(r.y_);
    r.x1_ = r.x0_ + width;
    r.y1_ = r.y0_ + height;
    // The edge planes' unit normals are (0, z0, -y0)/l0, (-z0, 0, x1)/l1, (0, -z0, y1)/l2 and
    // (z0, 0, -x0)/l3; the interior angle between neighbours is acos of minus their dot.
    const float z0sq = r.z0_ * r.z0_;
#if defined(__SSE2__)
    // Lanes 0-3: the four edges' l0..l3, then the four angles g0..g3 (as below).
    const __m128 along = _mm_setr_ps(r.y0_, r.x1_, r.y1_, r.x0_);
    const __m128 l = _mm_sqrt_ps(_mm_add_ps(_mm_set1_ps(z0sq), _mm_mul_ps(along, along)));
    const __m128 l_next = _mm_shuffle_ps(l, l, _MM_SHUFFLE(0, 3, 2, 1));  // l1, l2, l3, l0
    const __m128 numerator =
        _mm_mul_ps(_mm_setr_ps(r.y0_, -r.x1_, r.x0_, -r.x0_), _mm_setr_ps(r.x1_, r.y1_, r.y1_, r.y0_));
    std::array<float, 4> ls, gs, bs;
    _mm_storeu_ps(ls.data(), l);
    _mm_storeu_ps(gs.data(), interior_angles(_mm_div_ps(numerator, _mm_mul_ps(l, l_next))));
    // b0, b1 and 1 - b0^2 (as below) in a second division beside the cosines'.
    const __m128 l0l2 = _mm_shuffle_ps(l, l, _MM_SHUFFLE(0, 0, 2, 0));  // l0, l2, l0, l0
    _mm_storeu_ps(bs.data(), _mm_div_ps(_mm_setr_ps(-r.y0_, r.y1_, z0sq, 0.0f),
                                        _mm_mul_ps(l0l2, _mm_setr_ps(1.0f, 1.0f, ls[0], 1.0f))));
    const float g0 = gs[0], g1 = gs[1], g2 = gs[2], g3 = gs[3];
    r.b0_ = bs[0];
    r.b1_ = bs[1];
    r.one_minus_b0sq_ = bs[2];  // 1 - b0^2 without the cancellation
#else
    const float l0 = std::sqrt(z0sq + r.y0_ * r.y0_), l1 = std::sqrt(z0sq + r.x1_ * r.x1_),
                l2 = std::sqrt(z0sq + r.y1_ * r.y1_), l3 = std::sqrt(z0sq + r.x0_ * r.x0_);
    const float g0 = interior_angle(r.y0_ * r.x1_ / (l0 * l1)), g1 = interior_angle(-r.x1_ * r.y1_ / (l1 * l2)),
                g2 = interior_angle(r.x0_ * r.y1_ / (l2 * l3)), g3 = interior_angle(-r.x0_ * r.y0_ / (l3 * l0));
    r.b0_ = -r.y0_ / l0;
    r.one_minus_b0sq_ = z0sq / (l0 * l0);  // 1 - b0^2 without the cancellation
    r.b1_ = r.y1_ / l2;
#endif
    r.k_ = 2.0f * kPiF - g2 - g3;
    r.solid_angle_ = g0 + g1 - r.k_;
    if (!(r.solid_angle_ > kMinSolidAngle)) return std::nullopt;
    return r;
}

Vec3f SphericalRectangle::sample(float u, float v) const {
    // The x of the sample: the solid angle left of it is u times the whole.
    const float au = u * solid_angle_ + k_;
    const SinCos a = fast_sincos(au);  // accurate near au = pi too, where sin(au) vanishes
    // The paper's fu = n / sin(au), n = cos(au) b0 - b1.  With cu = +/-1 / sqrt(F),
    // F = fu^2 + b0^2 >= 1, its xu = -cu z0 / sqrt(1 - cu^2) is -/+z0 / sqrt(F - 1), and
    // F - 1 = (n^2 - (1 - b0^2) sin^2) / sin^2, so xu = -/+z0 sin / sqrt(n^2 - (1 - b0^2) sin^2)
    // (the sign that of -fu taken as n's against sin's): one square root and one division.
    const float n = a.cos * b0_ - b1_, sin2 = a.sin * a.sin;
    const float t = z0_ * a.sin / std::sqrt(std::max(1e-14f * sin2, n * n - one_minus_b0sq_ * sin2));
    const float xu = std::clamp(n > 0.0f ? -t : t, x0_, x1_);
    // Its y: uniform in the projected height of that column.
    const float dist2 = xu * xu + z0_ * z0_;
#if defined(__SSE2__)
    // h0 and h1 in two lanes: one square root and one division for both (same floats).
    const __m128 ys = _mm_setr_ps(y0_, y1_, 0.0f, 0.0f);
    std::array<float, 4> hs;
    _mm_storeu_ps(hs.data(), _mm_div_ps(ys, _mm_sqrt_ps(_mm_add_ps(_mm_set1_ps(dist2), _mm_mul_ps(ys, ys)))));
    const float h0 = hs[0], h1 = hs[1];
#else
    const float h0 = y0_ / std::sqrt(dist2 + y0_ * y0_), h1 = y1_ / std::sqrt(dist2 + y1_ * y1_);
#endif
    const float hv = h0 + v * (h1 - h0), hv2 = hv * hv;
    const float yv = hv2 < 1.0f - 1e-6f ? std::clamp(hv * std::sqrt(dist2 / (1.0f - hv2)), y0_, y1_) : y1_;
    return origin_ + xu * x_ + yv * y_ + z0_ * z_;
}

}  // namespace foldcast::render
