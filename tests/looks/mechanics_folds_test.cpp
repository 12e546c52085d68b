// The looks' mechanics move the drape model's folds in the direction textile practice
// expects: stiff, heavy denim makes fewer and broader folds than limp, light chiffon hung the
// same way.
#include <gtest/gtest.h>

#include <cstdio>

#include "foldcast/drape/drape.hpp"
#include "foldcast/looks/looks.hpp"
#include "shipped_looks.hpp"

using namespace foldcast;

namespace {

drape::FoldSolution solve(const char* look, double width_m, double height_m, double inset_m) {
    return drape::solve_folds(
        drape::cloth_from_look(test::shipped_looks().get(look).mechanics, width_m, height_m, inset_m));
}

// Mean vertical distance between neighbouring fold lines at the centre (a_{i-1} - a_i).
double fold_spacing_m(const drape::FoldSolution& s) {
    return (s.amplitudes_m.front() - s.amplitudes_m.back()) / s.folds;
}

struct Size {
    double width_m, height_m, inset_m;
};
// A scarf-sized piece, a curtain-sized one and a small swatch (where denim is too stiff to
// fold at all: zero folds is fewer too).
const Size kSizes[] = {{0.5, 0.7, 0.1}, {1.0, 1.2, 0.2}, {0.3, 0.4, 0.05}};
}  // namespace

TEST(LookMechanics, DenimFoldsFewerAndBroaderThanChiffon) {
    for (const Size& size : kSizes) {
        SCOPED_TRACE(std::to_string(size.width_m) + " x " + std::to_string(size.height_m));
        const auto denim = solve("denim", size.width_m, size.height_m, size.inset_m);
        const auto chiffon = solve("chiffon", size.width_m, size.height_m, size.inset_m);
        std::printf("%.2f x %.2f m, inset %.2f: denim n=%d Q=%.3f, chiffon n=%d Q=%.3f\n", size.width_m, size.height_m,
                    size.inset_m, denim.folds, denim.Q, chiffon.folds, chiffon.Q);
        ASSERT_EQ(chiffon.regime, drape::FoldSolution::Regime::wrinkled) << chiffon.explanation;
        EXPECT_LT(denim.folds, chiffon.folds);
        EXPECT_GT(denim.Q, chiffon.Q);
        // Where denim folds at all, its folds are further apart.
        if (denim.regime == drape::FoldSolution::Regime::wrinkled) {
            EXPECT_GT(fold_spacing_m(denim), fold_spacing_m(chiffon));
        }
    }
}

TEST(LookMechanics, StiffnessOrderGivesFoldCountOrder) {
    // Canvas (stiffest per weight) <= denim <= poplin <= chiffon in number of folds.
    const int canvas = solve("canvas", 0.5, 0.7, 0.1).folds;
    const int denim = solve("denim", 0.5, 0.7, 0.1).folds;
    const int poplin = solve("cotton_poplin", 0.5, 0.7, 0.1).folds;
    const int chiffon = solve("chiffon", 0.5, 0.7, 0.1).folds;
    EXPECT_LE(canvas, denim);
    EXPECT_LE(denim, poplin);
    EXPECT_LE(poplin, chiffon);
    EXPECT_LT(canvas, chiffon);
}

TEST(LookMechanics, EveryShippedLookDrapesWithoutError) {
    for (const auto& name : test::shipped_looks().names()) {
        const auto solution = solve(name.c_str(), 0.5, 0.7, 0.1);
        EXPECT_FALSE(solution.explanation.empty()) << name;
        EXPECT_NE(solution.regime, drape::FoldSolution::Regime::no_feasible_folds)
            << name << ": " << solution.explanation;
    }
}
