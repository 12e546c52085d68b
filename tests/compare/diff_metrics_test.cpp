// diff metrics against values computed by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "compare_test_util.hpp"
#include "foldcast/compare/diff.hpp"

using namespace foldcast;
using foldcast::test::constant_image;

TEST(DiffMetrics, OneChangedValueGivesHandComputedErrors) {
    compare::Image a = constant_image(4, 4, 3, 0.5f);
    compare::Image b = a;
    b.at(1, 2, 0) = 0.75f;
    compare::DiffThresholds th;
    th.fail = 0.1;
    th.fail_percent = 10.0;  // 1 of 16 pixels = 6.25 % fails: not a failure
    const compare::DiffReport r = compare::diff_images(a, b, th);
    EXPECT_NEAR(r.mean_abs_error, 0.25 / 48.0, 1e-9);
    EXPECT_NEAR(r.max_abs_error, 0.25, 1e-9);
    EXPECT_EQ(r.max_x, 1);
    EXPECT_EQ(r.max_y, 2);
    EXPECT_EQ(r.max_channel, 0);
    EXPECT_NEAR(r.rms_error, std::sqrt(0.0625 / 48.0), 1e-9);
    EXPECT_NEAR(r.psnr_db, 20.0 * std::log10(1.0 / std::sqrt(0.0625 / 48.0)), 1e-6);
    EXPECT_EQ(r.fail_pixels, 1);
    EXPECT_EQ(r.warn_pixels, 1);  // default warn threshold 1e-6
    EXPECT_NEAR(r.fail_percent, 6.25, 1e-9);
    EXPECT_EQ(r.verdict, compare::DiffVerdict::warning);  // warnpercent 0
    th.warn = 0.3;
    EXPECT_EQ(compare::diff_images(a, b, th).verdict, compare::DiffVerdict::pass);
    th.hard_fail = 0.2;  // 0.25 exceeds it
    EXPECT_EQ(compare::diff_images(a, b, th).verdict, compare::DiffVerdict::failure);
    th.hard_fail = 1.0;
    th.fail_percent = 5.0;  // 6.25 % > 5 %
    EXPECT_EQ(compare::diff_images(a, b, th).verdict, compare::DiffVerdict::failure);
    // idiff's first rule: no failing pixel means PASS, whatever the warnings and hard limits.
    th.fail = 0.3;
    th.warn = 0.01;
    th.hard_fail = 0.2;
    EXPECT_EQ(compare::diff_images(a, b, th).verdict, compare::DiffVerdict::pass);
    th.fail = 0.1;
    th.allow_failures = 1;
    EXPECT_EQ(compare::diff_images(a, b, th).verdict, compare::DiffVerdict::pass);
}

TEST(DiffMetrics, IdenticalImagesPassWithInfinitePsnr) {
    const compare::Image a = constant_image(20, 15, 3, 0.3f);
    const compare::DiffReport r = compare::diff_images(a, a, {});
    EXPECT_EQ(r.verdict, compare::DiffVerdict::pass);
    EXPECT_EQ(r.max_abs_error, 0.0);
    EXPECT_TRUE(std::isinf(r.psnr_db));
    EXPECT_NEAR(r.ssim, 1.0, 1e-12);
    EXPECT_EQ(r.flip_mean, 0.0);
}

TEST(DiffMetrics, SizeOrChannelMismatchThrows) {
    EXPECT_THROW(compare::diff_images(constant_image(4, 4, 3, 0), constant_image(5, 4, 3, 0), {}),
                 compare::SizeMismatch);
    EXPECT_THROW(compare::diff_images(constant_image(4, 4, 3, 0), constant_image(4, 4, 4, 0), {}),
                 compare::SizeMismatch);
}

TEST(Ssim, ConstantImagesGiveLuminanceTermOnly) {
    // mu_a = 0.2, mu_b = 0.6, no variance: SSIM = (2 mu_a mu_b + C1) / (mu_a^2 + mu_b^2 + C1).
    const double c1 = 1e-4;
    const double expected = (2 * 0.2 * 0.6 + c1) / (0.04 + 0.36 + c1);
    EXPECT_NEAR(compare::ssim_luma(constant_image(16, 16, 1, 0.2f), constant_image(16, 16, 1, 0.6f)), expected, 1e-6);
}

TEST(Ssim, ContrastReversalIsNegativeAndNoiseLowersIt) {
    compare::Image a(32, 32, 1), b(32, 32, 1), c(32, 32, 1);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const float v = ((x / 4 + y / 4) % 2) ? 0.8f : 0.2f;
            a.at(x, y, 0) = v;
            b.at(x, y, 0) = 1.0f - v;
            c.at(x, y, 0) = v + (((x * 7 + y * 13) % 5) - 2) * 0.02f;
        }
    EXPECT_LT(compare::ssim_luma(a, b), -0.9);
    const double noisy = compare::ssim_luma(a, c);
    EXPECT_LT(noisy, 0.999);
    EXPECT_GT(noisy, 0.8);
}

TEST(Flip, BlackAgainstWhiteMatchesHandComputedColourError) {
    // Constant images: CSF filtering keeps them, features are zero, so FLIP = colour term.
    // CIELAB of sRGB primaries (D65): green (87.737, -86.185, 83.181), blue (32.303, 79.197, -107.864).
    auto hunt_ab = [](double L, double v) { return 0.01 * L * v; };
    const double hyab_gb = std::abs(87.737 - 32.303) + std::hypot(hunt_ab(87.737, -86.185) - hunt_ab(32.303, 79.197),
                                                                  hunt_ab(87.737, 83.181) - hunt_ab(32.303, -107.864));
    const double cmax = std::pow(hyab_gb, 0.7);
    const double de = std::pow(100.0, 0.7);  // white L=100 vs black L=0, a=b=0
    const double expected = 0.95 + (de - 0.4 * cmax) / (cmax - 0.4 * cmax) * 0.05;
    const auto map = compare::flip_error_map(constant_image(24, 24, 3, 0.0f), constant_image(24, 24, 3, 1.0f));
    for (float f : map) ASSERT_NEAR(f, expected, 2e-3);
    // A small grey step: below p_c * cmax, so linear in the HyAB^0.7 distance.
    const auto small = compare::flip_error_map(constant_image(24, 24, 3, 0.5f), constant_image(24, 24, 3, 0.52f));
    EXPECT_GT(small[0], 0.0f);
    EXPECT_LT(small[0], 0.95f * 0.5f);
}

TEST(Flip, ShiftedEdgeIsSeenAndIdenticalIsZero) {
    compare::Image a(40, 40, 3), b(40, 40, 3);
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x)
            for (int c = 0; c < 3; ++c) {
                a.at(x, y, c) = x < 20 ? 0.1f : 0.9f;
                b.at(x, y, c) = x < 22 ? 0.1f : 0.9f;
            }
    const auto same = compare::flip_error_map(a, a);
    for (float f : same) ASSERT_EQ(f, 0.0f);
    const auto shifted = compare::flip_error_map(a, b);
    EXPECT_GT(shifted[20 * 40 + 21], 0.5f);  // the pixels that changed colour
    EXPECT_LT(shifted[20 * 40 + 5], 1e-3f);  // far from the edge
}
