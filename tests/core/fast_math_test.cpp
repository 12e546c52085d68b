// The fast sin, cos and exp against libm (in double) over dense sweeps of the ranges the
// path tracer and the denoiser pass them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "foldcast/core/fast_math.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast {
namespace {

TEST(FastMath, SinCosTurnsAgreesWithLibm) {
    double worst_abs = 0.0, worst_rel = 0.0;
    for (int i = 0; i <= 1 << 20; ++i) {
        const float u = static_cast<float>(i) * 0x1.0p-20f;  // [0, 1], every quadrant edge included
        const SinCos f = sincos_turns(u);
        const double a = 2.0 * kPi * static_cast<double>(u);
        worst_abs = std::max({worst_abs, std::abs(f.sin - std::sin(a)), std::abs(f.cos - std::cos(a))});
        // Relative error of sin where it is not exactly zero (at multiples of half a turn it is 0
        // exactly, and libm's of the double 2 pi u is not); the reduction is exact in turns.
        if (i % (1 << 19) != 0) worst_rel = std::max(worst_rel, std::abs(f.sin / std::sin(a) - 1.0));
    }
    EXPECT_LT(worst_abs, 2e-7);
    EXPECT_LT(worst_rel, 1e-6);
    // Negative turns as well.
    const SinCos f = sincos_turns(-0.3f);
    EXPECT_NEAR(f.sin, std::sin(-0.6 * kPi), 2e-7);
    EXPECT_NEAR(f.cos, std::cos(-0.6 * kPi), 2e-7);
}

TEST(FastMath, SinCosRadiansAgreesWithLibm) {
    double worst_abs = 0.0, worst_rel = 0.0;
    for (int i = -(1 << 20); i <= 1 << 20; ++i) {
        const float x = static_cast<float>(i) * 0x1.0p-16f;  // [-16, 16] radians
        const SinCos f = fast_sincos(x);
        const double s = std::sin(static_cast<double>(x)), c = std::cos(static_cast<double>(x));
        worst_abs = std::max({worst_abs, std::abs(f.sin - s), std::abs(f.cos - c)});
        if (std::abs(s) > 1e-3) worst_rel = std::max(worst_rel, std::abs(f.sin / s - 1.0));
    }
    EXPECT_LT(worst_abs, 2e-7);
    EXPECT_LT(worst_rel, 1e-6);
    // Close to pi, where the spherical rectangle divides by sin: the three-part reduction keeps
    // the relative accuracy.
    for (const float x : {std::nextafter(kPiF, 0.0f), kPiF, std::nextafter(kPiF, 4.0f), 2.0f * kPiF}) {
        const double s = std::sin(static_cast<double>(x));
        EXPECT_NEAR(fast_sincos(x).sin / s, 1.0, 1e-5) << x;
    }
}

TEST(FastMath, ExpAgreesWithLibm) {
    double worst = 0.0;
    for (int i = -(1 << 20); i <= 1 << 20; ++i) {
        const float x = static_cast<float>(i) * (80.0f / (1 << 20));  // [-80, 80]
        const double e = std::exp(static_cast<double>(x));
        worst = std::max(worst, std::abs(fast_exp(x) / e - 1.0));
    }
    EXPECT_LT(worst, 3e-7);
    EXPECT_EQ(fast_exp(0.0f), 1.0f);
    EXPECT_GT(fast_exp(-200.0f), 0.0f);  // clamped to the normal range, not 0 or a denormal
    EXPECT_LT(fast_exp(-200.0f), 1e-37f);
}

TEST(FastMath, Log2AndExp2AgreeWithLibm) {
    double worst_log = 0.0, worst_exp2 = 0.0;
    for (int i = 1; i <= 1 << 20; ++i) {
        const float x = static_cast<float>(i) * 0x1.0p-18f;  // (0, 4]
        const double l = std::log2(static_cast<double>(x));
        worst_log = std::max(worst_log, std::abs(fast_log2(x) - l) / (1.0 + std::abs(l)));  // ~2 ulp
        const float y = static_cast<float>(i - (1 << 19)) * 0x1.0p-14f;                     // [-32, 32]
        worst_exp2 = std::max(worst_exp2, std::abs(fast_exp2(y) / std::exp2(static_cast<double>(y)) - 1.0));
    }
    EXPECT_LT(worst_log, 3e-7);  // of 1 + |log2 x|
    EXPECT_LT(worst_exp2, 3e-7);
    EXPECT_EQ(fast_log2(1.0f), 0.0f);
    EXPECT_EQ(fast_log2(0.25f), -2.0f);
    EXPECT_EQ(fast_exp2(3.0f), 8.0f);
}

TEST(FastMath, PowOfUnitIntervalAgreesWithLibm) {
    double worst = 0.0;
    for (const float y : {0.5f, 3.7f, 20.0f, 100.0f})
        for (int i = 1; i <= 1 << 16; ++i) {
            const float x = static_cast<float>(i) * 0x1.0p-16f;  // (0, 1]
            const double p = std::pow(static_cast<double>(x), static_cast<double>(y));
            if (p < 1e-30) continue;  // beside the float range's end
            worst = std::max(worst, std::abs(fast_pow_unit(x, y) / p - 1.0) / (1.0 + std::abs(std::log2(p))));
        }
    EXPECT_LT(worst, 4e-7);  // of 1 + |log2 x^y|
    EXPECT_LT(fast_pow_unit(0.0f, 2.0f), 1e-30f);
}

#if defined(__SSE2__)
TEST(FastMath, ExpLanesAreTheScalarFloats) {
    for (int i = -4000; i < 4000; i += 4) {
        alignas(16) float x[4], y[4];
        for (int k = 0; k < 4; ++k) x[k] = static_cast<float>(i + k) * 0.0137f;
        _mm_store_ps(y, fast_exp4(_mm_load_ps(x)));
        for (int k = 0; k < 4; ++k) EXPECT_EQ(y[k], fast_exp(x[k])) << x[k];
    }
}
#endif

}  // namespace
}  // namespace foldcast
