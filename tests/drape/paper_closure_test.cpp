// The paper's closure (docs/drape.md, "The paper's closure") against the paper's published
// Tables 1 and 2, and the Simpson measure of the top edge against its closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "foldcast/drape/drape.hpp"
#include "paper_closure.hpp"

namespace foldcast::drape {
namespace {

struct PaperRow {
    double width_cm, height_cm, displacement_cm, thickness_mm, young_mpa, weight_1e7_n_mm2;
    int folds;
    double zmax_cm, q;
};

// Tables 1 and 2: each support displaced by d (the inset).
constexpr PaperRow kRows[] = {
    {140, 90, 10, 0.25, 165, 15, 5, 5.4, 1.31},  {140, 140, 10, 0.25, 165, 15, 7, 4.8, 1.29},
    {140, 235, 10, 0.25, 165, 15, 8, 6.0, 1.34}, {90, 145, 8.5, 0.35, 150, 10, 4, 5.60, 1.78},
    {90, 145, 8.5, 0.35, 150, 33, 6, 4.60, 1.46}, {90, 145, 8.5, 0.35, 150, 54, 7, 4.40, 1.39},
};

ClothParams paper_cloth(const PaperRow& r) {
    ClothParams p;
    p.width_m = r.width_cm * 1e-2;
    p.height_m = r.height_cm * 1e-2;
    p.inset_m = r.displacement_cm * 1e-2;
    p.thickness_m = r.thickness_mm * 1e-3;
    p.young_pa = r.young_mpa * 1e6;
    p.weight_n_per_m2 = r.weight_1e7_n_mm2 * 1e-7 * 1e6;
    p.closure = Closure::paper;
    return p;
}

// Every row but the tallest cloth's: there the paper prints 8 folds with Q = 1.34, while its
// critical-stress equation gives Q = 1.167 for h = 2.35 m (1.224 at h = 1.4 m), and the top
// edge alone then needs log(a_0/a_n)/log Q > 13 folds under any reading of the iteration
// (docs/drape.md works it through).  The row is printed, and checked to stay that far off,
// so that a change which makes it agree is noticed and the docs updated.
TEST(PaperClosure, ReproducesThePublishedFoldCounts) {
    std::printf("%-28s %9s %14s %12s\n", "cloth (L x h, d; w)", "n", "zmax cm", "Q");
    for (const PaperRow& r : kRows) {
        const FoldSolution s = solve_folds(paper_cloth(r));
        std::printf("%3.0f x %3.0f cm, d %4.1f; w %2.0f   %2d (%d)   %5.2f (%4.2f)   %4.2f (%4.2f)\n", r.width_cm,
                    r.height_cm, r.displacement_cm, r.weight_1e7_n_mm2, s.folds, r.folds, s.zmax_m * 100, r.zmax_cm,
                    s.Q, r.q);
        ASSERT_EQ(s.closure, Closure::paper);
        ASSERT_EQ(s.regime, FoldSolution::Regime::wrinkled);
        if (r.height_cm == 235) {
            EXPECT_GE(s.folds, 12) << "the tallest row now agrees better: update docs/drape.md";
            continue;
        }
        EXPECT_LE(std::abs(s.folds - r.folds), 1) << r.width_cm << " x " << r.height_cm << " w " << r.weight_1e7_n_mm2;
        EXPECT_NEAR(s.Q, r.q, 0.15 * r.q);
    }
}

// The paper's answer is on its bands, not on the roots: top edge within 5 % of L, a_0 = 1.01 h,
// the amplitudes in the reported ratio Q.
TEST(PaperClosure, AnswerMeetsItsOwnStoppingRule) {
    for (const PaperRow& r : kRows) {
        const ClothParams p = paper_cloth(r);
        const FoldSolution s = solve_folds(p);
        ASSERT_EQ(s.amplitudes_m.size(), std::size_t(s.folds) + 1);
        EXPECT_NEAR(s.amplitudes_m.front(), 1.01 * p.height_m, 1e-12);
        const double top = top_edge_length_m(p.support_span_m(), std::hypot(s.amplitudes_m.back(), s.zmax_m));
        EXPECT_NEAR(top, p.width_m, 0.05 * p.width_m + 1e-4);
        for (std::size_t i = 1; i < s.amplitudes_m.size(); ++i)
            EXPECT_NEAR(s.amplitudes_m[i - 1] / s.amplitudes_m[i], s.Q, 1e-9);
        EXPECT_GT(s.closure_steps, 0);
        EXPECT_LT(s.residual, 0.1);
    }
}

TEST(PaperClosure, SimpsonTopEdgeAgreesWithTheClosedForm) {
    for (double a : {0.0, 0.05, 0.2, 0.6})
        EXPECT_NEAR(detail::top_edge_length_simpson_m(1.2, a, 32), top_edge_length_m(1.2, a), 1e-6);
}

TEST(PaperClosure, KeepsTheRegimesOfTheDefaultClosure) {
    ClothParams p;
    p.closure = Closure::paper;
    p.thickness_m = 1e-3;  // S > 1
    EXPECT_EQ(solve_folds(p).regime, FoldSolution::Regime::no_wrinkles);
    p = ClothParams{};
    p.closure = Closure::paper;
    p.inset_m = 0.0;
    EXPECT_EQ(solve_folds(p).regime, FoldSolution::Regime::no_feasible_folds);
}

TEST(PaperClosure, NamesRoundTrip) {
    Closure c = Closure::hem;
    EXPECT_TRUE(closure_from_name("paper", c));
    EXPECT_EQ(c, Closure::paper);
    EXPECT_STREQ(closure_name(c), "paper");
    EXPECT_TRUE(closure_from_name("hem", c));
    EXPECT_EQ(c, Closure::hem);
    EXPECT_FALSE(closure_from_name("Paper", c));
    EXPECT_FALSE(closure_from_name("", c));
}

// A garment and an animation on the paper's answer: the grid builds, keeps its supports and
// relaxes like the default closure's.
TEST(PaperClosure, BuildsAGarment) {
    ClothParams p;
    p.closure = Closure::paper;
    const FoldSolution s = solve_folds(p);
    ASSERT_GE(s.folds, 1);
    const Garment g = build_garment(p, s, {33, 33});
    EXPECT_LT(g.stretch.max, 0.05);
    for (const auto& v : g.mesh.positions) ASSERT_TRUE(v.allFinite());
}

}  // namespace
}  // namespace foldcast::drape
