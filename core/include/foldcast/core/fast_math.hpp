#pragma once
// sin, cos, exp, exp2, log2 and pow for the path tracer's inner loops, inline and without
// branches: libm's sincosf, expf and powf were 6 % of a turntable's CPU, mostly the call and its argument checks
// for ranges the tracer never passes.  Each is a range reduction and a short polynomial on
// the reduced range, the coefficients fitted here (Lawson-iterated least squares for the
// smallest largest relative error, in long double; the fit is not part of the build).
// Accuracy, checked by tests/core/fast_math_test.cpp against libm: sin and cos within 2e-7
// absolute and sin within 1e-6 relative away from its zeros (in turns: also near them), exp
// within 3e-7 relative, log2 within 3e-7 (1 + |log2 x|).  No FMA under the x86-64 baseline, so the SSE2 lanes of
// fast_exp4 give the scalar function's floats.
#include <bit>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace foldcast {

struct SinCos {
    float sin, cos;
};

namespace fast_math_detail {

// x rounded to the nearest integer (ties to even), for |x| < 2^22: adding 1.5 * 2^23 leaves
// no fraction bits.  The compiler may not fold it (no -ffast-math).
inline float round_nearest(float x) {
    constexpr float kShift = 0x1.8p23f;
    return (x + kShift) - kShift;
}

// sin and cos of r + q pi/2 for r in [-pi/4, pi/4]: the two polynomials, exchanged and
// negated by the quadrant's bits with masks rather than branches.
inline SinCos quadrant_sincos(float r, std::int32_t q) {
    const float z = r * r;
    // sin r = r + r^3 (s0 + s1 r^2 + s2 r^4), relative error < 4e-9 on the range.
    const float s = r + (r * z) * (-1.6666654610e-01f + z * (8.3321607615e-03f + z * -1.9515283148e-04f));
    // cos r = 1 - r^2 / 2 + r^4 (c0 + c1 r^2 + c2 r^4), error < 2e-10.
    const float c = 1.0f - 0.5f * z + (z * z) * (4.1666645683e-02f + z * (-1.3887316254e-03f + z * 2.4433156977e-05f));
    const std::uint32_t swap = 0u - static_cast<std::uint32_t>(q & 1);  // odd quadrant: sin and cos exchange
    const std::uint32_t sb = std::bit_cast<std::uint32_t>(s), cb = std::bit_cast<std::uint32_t>(c);
    const std::uint32_t sin_bits = (sb & ~swap) | (cb & swap), cos_bits = (cb & ~swap) | (sb & swap);
    // sin is negative in quadrants 2 and 3, cos in 1 and 2.
    const std::uint32_t sin_sign = static_cast<std::uint32_t>(q & 2) << 30;
    const std::uint32_t cos_sign = static_cast<std::uint32_t>((q + 1) & 2) << 30;
    return {std::bit_cast<float>(sin_bits ^ sin_sign), std::bit_cast<float>(cos_bits ^ cos_sign)};
}

}  // namespace fast_math_detail

// sin and cos of 2 pi u (u in turns, |u| < 2^20).  The reduction is exact: 4u less its
// nearest integer is a float with no rounding, so the error is the polynomials' and one
// product's, also near the zeros.
inline SinCos sincos_turns(float u) {
    const float t = 4.0f * u;
    const float k = fast_math_detail::round_nearest(t);
    return fast_math_detail::quadrant_sincos((t - k) * 1.57079632679f, static_cast<std::int32_t>(k));
}

// sin and cos of x radians, |x| < 2^15.  Cody and Waite's reduction by pi/2 in three parts
// (8, 12 and 24 significant bits), so that k times the first two is exact: the reduced
// argument keeps its relative accuracy near multiples of pi.
inline SinCos fast_sincos(float x) {
    const float k = fast_math_detail::round_nearest(x * 0x1.45f306p-1f);  // x / (pi/2)
    const float r = ((x - k * 0x1.92p+0f) - k * 0x1.fb6p-12f) - k * -0x1.777a5cp-25f;
    return fast_math_detail::quadrant_sincos(r, static_cast<std::int32_t>(k));
}

// e^x, x clamped to [-87, 88] (the normal floats' range): x = k ln 2 + r with |r| <= ln 2 / 2
// (ln 2 in two parts, the first of 9 bits), e^r by a polynomial, 2^k in the exponent bits.
inline float fast_exp(float x) {
    x = x < -87.0f ? -87.0f : (x > 88.0f ? 88.0f : x);
    const float k = fast_math_detail::round_nearest(x * 0x1.715476p+0f);  // x / ln 2
    const float r = (x - k * 0x1.63p-1f) - k * -0x1.bd0106p-13f;
    // e^r = 1 + r + r^2 (e0 + e1 r + ... + e4 r^4), relative error < 4e-9 on the range.
    const float p =
        1.0f + (r + (r * r) * (4.9999993452e-01f +
                               r * (1.6666520690e-01f +
                                    r * (4.1668387365e-02f + r * (8.3687098318e-03f + r * 1.3814613093e-03f)))));
    const auto scale = std::bit_cast<float>(static_cast<std::uint32_t>(static_cast<std::int32_t>(k) + 127) << 23);
    return p * scale;
}

// 2^y, y clamped to [-126, 127]: 2^k in the exponent bits times e^((y - k) ln 2), exp's
// polynomial (the product's rounding adds < 6e-8 relative).
inline float fast_exp2(float y) {
    y = y < -126.0f ? -126.0f : (y > 127.0f ? 127.0f : y);
    const float k = fast_math_detail::round_nearest(y);
    const float r = (y - k) * 0.693147181f;
    const float p =
        1.0f + (r + (r * r) * (4.9999993452e-01f +
                               r * (1.6666520690e-01f +
                                    r * (4.1668387365e-02f + r * (8.3687098318e-03f + r * 1.3814613093e-03f)))));
    return p * std::bit_cast<float>(static_cast<std::uint32_t>(static_cast<std::int32_t>(k) + 127) << 23);
}

// log2 x for a normal positive x: x = 2^e m with m in [sqrt(1/2), sqrt(2)) taken from the bits
// (subtracting sqrt(1/2)'s bits puts that range's exponent at 0), then log2 m = (m - 1) L(m - 1)
// by a degree-7 polynomial, absolute error < 5e-8 |log2 m| plus the float roundings.
inline float fast_log2(float x) {
    const auto bits = std::bit_cast<std::int32_t>(x);
    const std::int32_t e = (bits - 0x3f3504f3) >> 23;  // arithmetic shift: floor
    const float m = std::bit_cast<float>(bits - static_cast<std::int32_t>(static_cast<std::uint32_t>(e) << 23)) - 1.0f;
    const float l = 1.4426947724e+00f +
                    m * (-7.2135714893e-01f +
                         m * (4.8093944476e-01f +
                              m * (-3.6008721557e-01f +
                                   m * (2.8670745711e-01f +
                                        m * (-2.5006904690e-01f + m * (2.3689036679e-01f + m * -1.4574444206e-01f))))));
    return static_cast<float>(e) + m * l;
}

// x^y for x in [0, 1] and y > 0 (the sheen's sin^(1/alpha)): 2^(y log2 x), x below 1e-30
// taken as 1e-30 (its power is then below 2^-99 y, nothing beside the lobe's other terms).
// Relative error below 4e-7 (1 + |y log2 x|).
inline float fast_pow_unit(float x, float y) { return fast_exp2(y * fast_log2(x < 1e-30f ? 1e-30f : x)); }

#if defined(__SSE2__)
// fast_exp of four lanes: the same operations in the same order, so the same floats.
inline __m128 fast_exp4(__m128 x) {
    x = _mm_min_ps(_mm_max_ps(x, _mm_set1_ps(-87.0f)), _mm_set1_ps(88.0f));
    const __m128 shift = _mm_set1_ps(0x1.8p23f);
    const __m128 k = _mm_sub_ps(_mm_add_ps(_mm_mul_ps(x, _mm_set1_ps(0x1.715476p+0f)), shift), shift);
    const __m128 r =
        _mm_sub_ps(_mm_sub_ps(x, _mm_mul_ps(k, _mm_set1_ps(0x1.63p-1f))), _mm_mul_ps(k, _mm_set1_ps(-0x1.bd0106p-13f)));
    const auto madd = [&r](float c, __m128 t) { return _mm_add_ps(_mm_set1_ps(c), _mm_mul_ps(r, t)); };
    const __m128 poly =
        madd(4.9999993452e-01f,
             madd(1.6666520690e-01f, madd(4.1668387365e-02f, madd(8.3687098318e-03f, _mm_set1_ps(1.3814613093e-03f)))));
    const __m128 p = _mm_add_ps(_mm_set1_ps(1.0f), _mm_add_ps(r, _mm_mul_ps(_mm_mul_ps(r, r), poly)));
    const __m128i e = _mm_slli_epi32(_mm_add_epi32(_mm_cvttps_epi32(k), _mm_set1_epi32(127)), 23);
    return _mm_mul_ps(p, _mm_castsi128_ps(e));
}
#endif

}  // namespace foldcast
