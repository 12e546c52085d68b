// More supports (docs/drape.md): bays sharing their inner supports, each folding with its
// share of the width, and a support drop that shears the level pattern.
#include <gtest/gtest.h>

#include <cmath>

#include "foldcast/core/error.hpp"
#include "foldcast/drape/drape.hpp"

namespace foldcast::drape {
namespace {

// A curtain: 1.2 x 1.0 m on 5 hooks, 8 cm in from each corner.
ClothParams curtain(double drop_m = 0.0) {
    ClothParams p;
    p.width_m = 1.2;
    p.height_m = 1.0;
    p.inset_m = 0.08;
    p.thickness_m = 0.2e-3;
    p.young_pa = 3e6;
    p.weight_n_per_m2 = 0.12 * 9.80665;
    p.supports = 5;
    p.support_drop_m = drop_m;
    return p;
}
constexpr GridSize kGrid{65, 49};  // 4 bays of 16 cells

TEST(Supports, EachBayFoldsWithItsShareOfTheWidth) {
    const ClothParams p = curtain();
    ClothParams bay = p;
    bay.supports = 2;
    bay.width_m = p.width_m / 4;
    bay.inset_m = p.inset_m / 4;
    EXPECT_EQ(bay_params(p).width_m, bay.width_m);
    EXPECT_DOUBLE_EQ(bay_params(p).support_span_m(), p.support_span_m() / 4);
    const FoldSolution many = solve_folds(p), one = solve_folds(bay);
    ASSERT_EQ(many.regime, FoldSolution::Regime::wrinkled);
    EXPECT_GE(many.folds, 1);
    EXPECT_EQ(many.folds, one.folds);
    EXPECT_EQ(many.amplitudes_m, one.amplitudes_m);
    EXPECT_EQ(many.stress_ratio, stress_ratio(bay));
    // A bay is narrower than the whole span, so buckling is harder than over two supports.
    ClothParams two = p;
    two.supports = 2;
    EXPECT_GT(stress_ratio(p), stress_ratio(two));
}

TEST(Supports, EverySupportIsExactlyPinned) {
    for (double drop : {0.0, 0.06, -0.03}) {
        const ClothParams p = curtain(drop);
        const Garment g = build_garment(p, solve_folds(p), kGrid);
        ASSERT_EQ(g.support_vertices, (std::vector<int>{0, 16, 32, 48, 64}));
        for (int k = 0; k < 5; ++k) {
            const Vec3f& s = g.mesh.positions[std::size_t(g.support_vertices[std::size_t(k)])];
            const double x = -0.5 * p.support_span_m() + k * p.support_span_m() / 4;
            EXPECT_NEAR(s.x(), x, 1e-6) << k;
            EXPECT_NEAR(s.y(), -drop * k / 4, 1e-6) << k;
            EXPECT_EQ(s.z(), 0.0f) << k;
        }
    }
}

TEST(Supports, BaysAreCopiesOfOneBayJoinedAtTheSharedSupports) {
    const ClothParams p = curtain();
    const FoldSolution s = solve_folds(p);
    const Garment g = build_garment(p, s, kGrid, /*relax=*/false);  // the model's grid
    const ClothParams bay = bay_params(p);
    const Garment one = build_garment(bay, s, {17, kGrid.nv}, false);
    const double bay_span = bay.support_span_m();
    for (int j = 0; j < kGrid.nv; ++j)
        for (int k = 0; k < 4; ++k)
            for (int i = 0; i < 17; ++i) {
                const Vec3f& q = g.mesh.positions[std::size_t(j * kGrid.nu + k * 16 + i)];
                const Vec3f& r = one.mesh.positions[std::size_t(j * 17 + i)];
                const double centre = -0.5 * p.support_span_m() + (k + 0.5) * bay_span;
                ASSERT_NEAR(q.x(), centre + r.x(), 1e-6) << j << " " << k << " " << i;
                ASSERT_NEAR(q.y(), r.y(), 1e-6);
                ASSERT_NEAR(q.z(), r.z(), 1e-6);
            }
    // Continuous at the shared supports: the support column hangs straight down from its
    // support, and no edge there is longer or shorter than anywhere in a single bay.
    for (int j = 0; j < kGrid.nv; ++j)
        for (int col : {16, 32, 48}) {
            const Vec3f& q = g.mesh.positions[std::size_t(j * kGrid.nu + col)];
            EXPECT_NEAR(q.z(), 0.0, 1e-7);
            EXPECT_NEAR(q.y(), -p.height_m * j / (kGrid.nv - 1), 1e-6);
        }
    EXPECT_NEAR(g.stretch.max, one.stretch.max, 1e-6);
    ASSERT_EQ(g.fold_sign.size(), g.mesh.positions.size());
}

TEST(Supports, DropKeepsTheFoldsAndShearsThePattern) {
    const ClothParams level = curtain(), dropped = curtain(0.1);
    const FoldSolution a = solve_folds(level), b = solve_folds(dropped);
    EXPECT_EQ(a.folds, b.folds);
    EXPECT_EQ(a.amplitudes_m, b.amplitudes_m);
    EXPECT_EQ(a.zmax_m, b.zmax_m);
    // The model's grids: the relaxation of each is its own, not a shear of the other's.
    const Garment ga = build_garment(level, a, kGrid, false), gb = build_garment(dropped, b, kGrid, false);
    const double l = level.support_span_m();
    for (std::size_t v = 0; v < ga.mesh.positions.size(); ++v) {
        const Vec3f& p = ga.mesh.positions[v];
        const Vec3f& q = gb.mesh.positions[v];
        ASSERT_NEAR(q.x(), p.x(), 1e-6);
        ASSERT_NEAR(q.y(), p.y() - 0.1 * (p.x() + 0.5 * l) / l, 1e-6);
        ASSERT_NEAR(q.z(), p.z(), 1e-6);
    }
    // Two supports with a drop: the second one lower, same n as level.
    ClothParams two = curtain(0.05);
    two.supports = 2;
    ClothParams two_level = two;
    two_level.support_drop_m = 0.0;
    const Garment g2 = build_garment(two, solve_folds(two), {33, 33}, false);
    EXPECT_EQ(solve_folds(two).folds, solve_folds(two_level).folds);
    EXPECT_NEAR(g2.mesh.positions[32].y(), -0.05, 1e-6);
    // The fold lines are sheared the same way and still end on the supports.
    const auto lines = fold_lines(dropped, b, 9);
    ASSERT_EQ(lines.size(), std::size_t(4 * (b.folds + 1)));
    const FoldLine& last = lines.back();
    EXPECT_EQ(last.bay, 3);
    EXPECT_NEAR(last.points.back().x(), 0.5 * l, 1e-12);
    EXPECT_NEAR(last.points.back().y(), -0.1, 1e-12);
}

TEST(Supports, AnimationEndsOnTheGarment) {
    const ClothParams p = curtain(0.04);
    AnimationOptions options;
    options.frames = 4;
    options.relax = false;  // relaxed frames are warm-started, so only the model's grids are equal
    const Animation anim = animate(p, kGrid, options);
    const Garment g = build_garment(p, solve_folds(p), kGrid, false);
    ASSERT_EQ(anim.frames.back().size(), g.mesh.positions.size());
    for (std::size_t v = 0; v < g.mesh.positions.size(); ++v) ASSERT_EQ(anim.frames.back()[v], g.mesh.positions[v]);
    // Relaxed, every support of every bay stays where the model puts it in every frame.
    options.relax = true;
    const Animation relaxed = animate(p, kGrid, options);
    for (int v : g.support_vertices) EXPECT_EQ(relaxed.frames.back()[std::size_t(v)], g.mesh.positions[std::size_t(v)]);
}

TEST(Supports, RejectsBadSupportsAndGrids) {
    ClothParams p = curtain();
    p.supports = 1;
    EXPECT_THROW(solve_folds(p), InputError);
    p.supports = 66;
    EXPECT_THROW(solve_folds(p), InputError);
    p = curtain(2.0);  // more than the span
    EXPECT_THROW(solve_folds(p), InputError);
    p = curtain(std::nan(""));
    EXPECT_THROW(solve_folds(p), InputError);
    p = curtain();
    const FoldSolution s = solve_folds(p);
    try {
        build_garment(p, s, {64, 64});  // 63 is no multiple of 4 bays
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("multiple of the 4 bays"), std::string::npos) << e.what();
    }
    EXPECT_THROW(animate(p, {64, 64}, {}), InputError);
}

}  // namespace
}  // namespace foldcast::drape
