// The garment grid built on the fold lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "foldcast/core/error.hpp"
#include "foldcast/drape/drape.hpp"

namespace foldcast::drape {
namespace {

bool all_finite(const Mesh& m) {
    for (const Vec3f& p : m.positions)
        if (!p.allFinite()) return false;
    for (const Vec3f& n : m.normals)
        if (!n.allFinite()) return false;
    return true;
}

TEST(Garment, SupportsAtTheSupportPointsAndTopEdgeOnTheTopFoldLine) {
    const ClothParams p;
    const FoldSolution s = solve_folds(p);
    ASSERT_GT(s.folds, 0);
    const GridSize grid{49, 41};
    const Garment g = build_garment(p, s, grid, false);  // the model's surface
    ASSERT_EQ(g.support_vertices, (std::vector<int>{0, grid.nu - 1}));
    const double half = 0.5 * p.support_span_m();
    EXPECT_TRUE(g.mesh.positions[0].isApprox(Vec3f(float(-half), 0, 0), 1e-6f));
    EXPECT_TRUE(g.mesh.positions[std::size_t(grid.nu - 1)].isApprox(Vec3f(float(half), 0, 0), 1e-6f));
    // Top row: on the top fold line y = -a_n cos, z = s_n zmax cos, and as long as the top edge.
    const double an = s.amplitudes_m.back();
    const double sign = s.folds % 2 == 0 ? 1.0 : -1.0;
    double length = 0.0;
    for (int i = 0; i < grid.nu; ++i) {
        const Vec3f& q = g.mesh.positions[std::size_t(i)];
        const double c = std::cos(std::numbers::pi * q.x() / p.support_span_m());
        EXPECT_NEAR(q.y(), -an * c, 1e-6);
        EXPECT_NEAR(q.z(), sign * s.zmax_m * c, 1e-6);
        if (i > 0) length += (q - g.mesh.positions[std::size_t(i - 1)]).norm();
    }
    EXPECT_NEAR(length, p.width_m, 2e-3 * p.width_m);  // chords of the curve
    // The centre fibre zig-zags down to the lowest fold line (y = -a_0) and hangs straight
    // for the rest, h - Z: the hem at x = 0 is at y = -(a_0 + h - Z) = -(h - a_n).
    ASSERT_LT(s.fold_length_m, p.height_m);
    const Vec3f& hem_centre = g.mesh.positions[std::size_t(grid.nv - 1) * grid.nu + grid.nu / 2];
    EXPECT_NEAR(hem_centre.x(), 0.0, 1e-6);
    EXPECT_NEAR(hem_centre.y(), -(s.amplitudes_m.front() + p.height_m - s.fold_length_m), 1e-5);
    EXPECT_NEAR(hem_centre.y(), -(p.height_m - an), 1e-5);
    EXPECT_NEAR(hem_centre.z(), s.zmax_m, 1e-5);  // fold line 0 bulges towards the viewer
    // The hem row is as long as the top edge (the closure's second length equation).
    double hem_length = 0.0;
    for (int i = 1; i < grid.nu; ++i)
        hem_length += (g.mesh.positions[std::size_t((grid.nv - 1) * grid.nu + i)] -
                       g.mesh.positions[std::size_t((grid.nv - 1) * grid.nu + i - 1)])
                          .norm();
    EXPECT_NEAR(hem_length, p.width_m, 2e-3 * p.width_m);
}

TEST(Garment, MeshIsCompleteFiniteAndInUnitsOfCloth) {
    const ClothParams p;
    const GridSize grid{33, 21};
    const Garment g = build_garment(p, solve_folds(p), grid);
    const Garment model = build_garment(p, solve_folds(p), grid, false);
    EXPECT_NO_THROW(validate(g.mesh, "garment"));
    EXPECT_TRUE(all_finite(g.mesh));
    EXPECT_EQ(g.mesh.positions.size(), std::size_t(33 * 21));
    EXPECT_EQ(g.mesh.topology.triangles.size(), std::size_t(2 * 32 * 20));
    ASSERT_EQ(g.mesh.normals.size(), g.mesh.positions.size());
    for (const Vec3f& n : g.mesh.normals) EXPECT_NEAR(n.norm(), 1.0f, 1e-5f);
    ASSERT_EQ(g.fold_sign.size(), g.mesh.positions.size());
    float lo = 1, hi = -1;
    for (float f : g.fold_sign) {
        EXPECT_GE(f, -1.0f);
        EXPECT_LE(f, 1.0f);
        lo = std::min(lo, f);
        hi = std::max(hi, f);
    }
    EXPECT_LT(lo, -0.5f);  // both fold directions are present
    EXPECT_GT(hi, 0.5f);
    // UVs in metres: (0,0) at the left support, (L, h) at the right end of the hem.
    EXPECT_TRUE(g.mesh.topology.uvs.front().isApprox(Vec2f(0, 0)));
    EXPECT_TRUE(g.mesh.topology.uvs.back().isApprox(Vec2f(float(p.width_m), float(p.height_m))));
    // On the model's surface the side edges hang straight down from the supports.
    const Vec3f& bottom_left = model.mesh.positions[std::size_t(20 * 33)];
    EXPECT_NEAR(bottom_left.y(), -p.height_m, 1e-6);
    EXPECT_NEAR(bottom_left.z(), 0.0, 1e-6);
}

TEST(Garment, SmoothSagIsNearlyIsometric) {
    ClothParams p;
    p.thickness_m = 1e-3;  // S > 1: no wrinkles, every row is the top edge moved down
    const FoldSolution s = solve_folds(p);
    ASSERT_EQ(s.regime, FoldSolution::Regime::no_wrinkles);
    const Garment g = build_garment(p, s, {64, 64});
    EXPECT_LT(g.stretch.max, 2e-3);
    for (const Vec3f& q : g.mesh.positions) EXPECT_EQ(q.z(), 0.0f);
}

// Stretch of grid edges against rest length.  The fold surface is a kinematic construction,
// not an isometry (docs/drape.md): rows crossing the folds come out longer than the cloth.
// Bound achieved over realistic fabrics: mean < 0.35, max < 1.0; the relaxed grid keeps the
// issue's bounds (mean <= 0.5 %, max <= 3 %) over the same fabrics.
TEST(Garment, StretchIsBoundedAcrossFabrics) {
    for (double t_mm : {0.15, 0.3})
        for (double gsm : {80.0, 150.0, 300.0})
            for (double h : {0.4, 0.7, 1.2}) {
                looks::Mechanics m;
                m.thickness_mm = t_mm;
                m.gsm = gsm;
                const ClothParams p = cloth_from_look(m, 0.5, h, 0.1);
                const Garment g = build_garment(p, solve_folds(p), {64, 64});
                EXPECT_TRUE(all_finite(g.mesh));
                EXPECT_LT(g.stretch_analytical.mean, 0.35) << t_mm << " " << gsm << " " << h;
                EXPECT_LT(g.stretch_analytical.max, 1.0) << t_mm << " " << gsm << " " << h;
                EXPECT_GT(g.stretch_analytical.max, 0.0);
                EXPECT_LE(g.stretch.mean, 0.005) << t_mm << " " << gsm << " " << h;
                EXPECT_LE(g.stretch.max, 0.03) << t_mm << " " << gsm << " " << h;
            }
}

TEST(Garment, SmoothAtGridResolution) {
    // No kinks: along the centre fibre a fold crest turns the fibre round over several rows
    // of a fine grid.  A piecewise-linear zig-zag would turn by ~2.5 rad at a single vertex;
    // the smooth profile's tightest crest (radius a few mm here) turns < 0.6 rad per row.
    // The relaxed grid keeps the crests round too (its crest targets are spread over a
    // centimetre of fibre): measured 0.86 rad at its tightest row, bound 1.0.
    const ClothParams p;
    const GridSize grid{65, 257};
    for (bool relax : {false, true}) {
        const Garment g = build_garment(p, solve_folds(p), grid, relax);
        double worst = 0.0;
        for (int j = 1; j + 1 < grid.nv; ++j) {
            const auto at = [&](int row) {
                return g.mesh.positions[std::size_t(row * grid.nu + grid.nu / 2)].cast<double>();
            };
            const Eigen::Vector3d a = at(j) - at(j - 1), b = at(j + 1) - at(j);
            worst = std::max(worst, std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)));
        }
        EXPECT_LT(worst, relax ? 1.0 : 0.6) << (relax ? "relaxed" : "model");  // radians between consecutive edges
    }
}

TEST(Garment, FoldLinesMatchTheSolution) {
    const ClothParams p;
    const FoldSolution s = solve_folds(p);
    const auto lines = fold_lines(p, s, 33);
    ASSERT_EQ(lines.size(), std::size_t(s.folds) + 1);
    for (const FoldLine& line : lines) {
        EXPECT_EQ(line.sign, line.index % 2 == 0 ? 1 : -1);
        const Eigen::Vector3d& mid = line.points[16];
        EXPECT_NEAR(mid.y(), -s.amplitudes_m[std::size_t(line.index)], 1e-12);
        EXPECT_NEAR(mid.z(), line.sign * s.zmax_m, 1e-12);
        EXPECT_EQ(line.points.front(), Eigen::Vector3d(-0.5 * p.support_span_m(), 0, 0));
    }
}

TEST(Garment, RejectsBadGrids) {
    const ClothParams p;
    const FoldSolution s = solve_folds(p);
    EXPECT_THROW(build_garment(p, s, {1, 10}), InputError);
    EXPECT_THROW(build_garment(p, s, {10, 0}), InputError);
    EXPECT_THROW(build_garment(p, s, {100000, 10}), InputError);
}

}  // namespace
}  // namespace foldcast::drape
