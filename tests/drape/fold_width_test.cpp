// The fold width gives the fold count a length scale (docs/drape.md, "The fold width"): as the
// bending stiffness B vanishes the folds get finer as B^(1/4), so n grows no faster than
// B^(-1/4); with Q from the critical-stress equation alone (Q - 1 ~ B^(1/2)) it grew as
// B^(-1/2), to hundreds of folds for a limp cloth.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "foldcast/drape/drape.hpp"

namespace foldcast::drape {
namespace {

TEST(FoldWidth, FoldCountGrowsNoFasterThanTheWidthShrinks) {
    ClothParams p;  // the default cotton: 0.5 x 0.7 m, inset 0.1 m, 0.3 mm, 5 MPa
    const FoldSolution reference = solve_folds(p);
    ASSERT_EQ(reference.regime, FoldSolution::Regime::wrinkled);
    const double young_pa = p.young_pa;
    int previous = reference.folds;
    for (int step = 1; step <= 16; ++step) {  // down four decades of E (and of B)
        const double shrink = std::pow(10.0, step / 4.0);
        p.young_pa = young_pa / shrink;
        const FoldSolution s = solve_folds(p);
        ASSERT_EQ(s.regime, FoldSolution::Regime::wrinkled);
        // The width falls as E^(1/4): at most that many more folds, with one for rounding.
        const double allowed = reference.folds * std::pow(shrink, 0.25) + 1.0;
        std::printf("E / %-8.3g n = %d (at most %.1f), half-width %.4f m, Q %.4f\n", shrink, s.folds, allowed,
                    s.fold_half_width_m, s.Q);
        EXPECT_LE(s.folds, allowed) << "E = " << p.young_pa << " Pa";
        EXPECT_GE(s.folds, previous) << "E = " << p.young_pa << " Pa";  // softer: never fewer
        EXPECT_NEAR(s.fold_half_width_m * std::pow(shrink, 0.25), reference.fold_half_width_m,
                    1e-9 * reference.fold_half_width_m);
        previous = s.folds;
    }
    EXPECT_GE(previous, 2 * reference.folds);  // the count does grow as the cloth softens
}

TEST(FoldWidth, IsPerBayWithMoreSupports) {
    ClothParams p;
    p.width_m = 1.0;
    p.inset_m = 0.2;
    p.supports = 3;
    EXPECT_DOUBLE_EQ(fold_half_width_m(p), fold_half_width_m(bay_params(p)));
    ClothParams one = p;
    one.supports = 2;
    EXPECT_GT(fold_half_width_m(one), fold_half_width_m(p));  // the longer span: wider folds
}

}  // namespace
}  // namespace foldcast::drape
