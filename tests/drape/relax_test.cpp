// Relaxation towards isometry (foldcast/drape/relax.hpp): the cloth keeps its length, the model's
// fold layout survives, the supports stay exactly where the model puts them.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cmath>
#include <string>

#include "foldcast/core/error.hpp"
#include "foldcast/core/math.hpp"
#include "foldcast/drape/drape.hpp"
#include "foldcast/drape/relax.hpp"
#include "foldcast/looks/looks.hpp"

namespace foldcast::drape {
namespace {

// Every shipped look draped the default way (0.5 x 0.7 m, supports 0.1 m in).
std::vector<std::pair<std::string, ClothParams>> shipped_looks() {
    std::vector<std::pair<std::string, ClothParams>> out;
    const looks::Library library = looks::Library::load_default();
    for (const std::string& name : library.names())
        out.emplace_back(name, cloth_from_look(library.get(name).mechanics, 0.5, 0.7, 0.1));
    return out;
}

void expect_keeps_length(GridSize grid) {
    for (const auto& [name, p] : shipped_looks()) {
        const Garment g = build_garment(p, solve_folds(p), grid);
        EXPECT_LE(g.stretch.mean, 0.005) << name;
        EXPECT_LE(g.stretch.max, 0.03) << name;
        EXPECT_GT(g.stretch_analytical.mean, 0.05) << name;  // there was something to do
    }
}

TEST(Relax, EveryLookKeepsItsLengthAt64) { expect_keeps_length({64, 64}); }
TEST(Relax, EveryLookKeepsItsLengthAt128) { expect_keeps_length({128, 128}); }

// The relaxed net bends where the model's surface bends instead of kinking at every vertex
// (thread smoothing, docs/drape.md): its turn between quads stays within 0.15 rad of the
// model's own at the 90th percentile.  The same relaxation without the smoothing phase is the
// foil: it crumples most looks beyond that (default cotton at 64x64: 0.93 rad, the model's
// surface 0.72); only the stiff ones (canvas, denim: few folds) stay smooth either way.
void expect_smooth(GridSize grid) {
    constexpr double kSlack = 0.15;
    int crumpled_without = 0;
    for (const auto& [name, p] : shipped_looks()) {
        const FoldSolution s = solve_folds(p);
        const Garment relaxed = build_garment(p, s, grid);
        const Garment model = build_garment(p, s, grid, false);
        RelaxSettings plain;
        plain.smoothing_iterations = 0;
        std::vector<Vec3f> without = model.mesh.positions;
        GridRelaxer(p, grid, model.support_vertices, plain).relax(without, model.mesh.positions);
        const double turn = turn_p90(relaxed.mesh.positions, grid), turn_without = turn_p90(without, grid),
                     surface = turn_p90(model.mesh.positions, grid);
        std::printf("%s %dx%d: turn p90 %.3f rad (without smoothing %.3f, the model's surface %.3f)\n", name.c_str(),
                    grid.nu, grid.nv, turn, turn_without, surface);
        EXPECT_LE(turn, surface + kSlack) << name;
        if (turn_without > surface + kSlack) ++crumpled_without;
    }
    EXPECT_GE(crumpled_without, 6);  // the foil does crumple: the bound can fail
}
TEST(Relax, EveryLookBendsInsteadOfCrumplingAt64) { expect_smooth({64, 64}); }
TEST(Relax, EveryLookBendsInsteadOfCrumplingAt128) { expect_smooth({128, 128}); }

// The same n (sign changes of z down the centre fibre) and every crest's height within
// 1.5 cm of the model's a_i, for each look at 64x64 and 128x128; the model's own grid shows
// the same layout.
class FoldLayout : public ::testing::TestWithParam<std::string> {};

TEST_P(FoldLayout, SurvivesRelaxation) {
    const looks::Library library = looks::Library::load_default();
    const ClothParams p = cloth_from_look(library.get(GetParam()).mechanics, 0.5, 0.7, 0.1);
    const FoldSolution s = solve_folds(p);
    ASSERT_GT(s.folds, 0);
    double largest_gap_m = 0.0;
    for (const GridSize grid : {GridSize{64, 64}, GridSize{128, 128}})
        for (bool relax : {false, true}) {
            const Garment g = build_garment(p, s, grid, relax);
            const CentreFibreFolds folds = centre_fibre_folds(g.mesh.positions, grid);
            const std::string what = std::to_string(grid.nu) + (relax ? " relaxed" : " model");
            EXPECT_EQ(folds.sign_changes, s.folds) << what;
            ASSERT_EQ(folds.crest_heights_m.size(), s.amplitudes_m.size()) << what;
            for (std::size_t k = 0; k < folds.crest_heights_m.size(); ++k) {
                const double model = -s.amplitudes_m[s.amplitudes_m.size() - 1 - k];  // top first
                EXPECT_NEAR(folds.crest_heights_m[k], model, 0.015) << what << " crest " << k;
                largest_gap_m = std::max(largest_gap_m, std::abs(folds.crest_heights_m[k] - model));
            }
            std::printf("%s %s: largest crest gap %.2f cm\n", GetParam().c_str(), what.c_str(), 100.0 * largest_gap_m);
            largest_gap_m = 0.0;
        }
}

INSTANTIATE_TEST_SUITE_P(EveryShippedLook, FoldLayout, ::testing::ValuesIn(looks::Library::load_default().names()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string name = info.param;
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

TEST(Relax, SupportsStayExactlyPinned) {
    const ClothParams p;
    const GridSize grid{40, 50};
    const Garment model = build_garment(p, solve_folds(p), grid, false);
    const Garment relaxed = build_garment(p, solve_folds(p), grid);
    ASSERT_EQ(relaxed.support_vertices, model.support_vertices);
    for (int v : relaxed.support_vertices)
        EXPECT_EQ(relaxed.mesh.positions[std::size_t(v)], model.mesh.positions[std::size_t(v)]);
    EXPECT_GT(relaxed.relax_iterations, 0);
}

// Any set of pinned vertices (multi-bay garments pin more than two): each stays exactly at
// its target, the rest relaxes.
TEST(Relax, AnyPinnedSetStaysExact) {
    const ClothParams p;
    const GridSize grid{31, 25};
    const Garment model = build_garment(p, solve_folds(p), grid, false);
    const std::vector<int> pinned = {0, 10, 20, 30, 24 * 31 + 15};
    std::vector<Vec3f> targets = model.mesh.positions;
    targets[10] += Vec3f(0.0f, 0.01f, 0.0f);  // pinned targets are honoured even off the model
    std::vector<Vec3f> positions = model.mesh.positions;
    const RelaxReport report = GridRelaxer(p, grid, pinned).relax(positions, targets);
    for (int v : pinned) EXPECT_EQ(positions[std::size_t(v)], targets[std::size_t(v)]) << v;
    EXPECT_LT(report.after.mean, report.before.mean);
}

TEST(Relax, FlatClothIsLeftAlone) {
    ClothParams p;
    p.inset_m = 0.0;  // no slack: the flat sheet is already isometric
    const Garment g = build_garment(p, solve_folds(p), {16, 16});
    const Garment model = build_garment(p, solve_folds(p), {16, 16}, false);
    EXPECT_EQ(g.relax_iterations, 0);
    EXPECT_EQ(g.mesh.positions, model.mesh.positions);
}

TEST(Relax, CentreFibreAnalysisCountsSignChanges) {
    // A column whose z follows cos(3 pi v / h): three sign changes, crests at v = 0, h/3,
    // 2h/3, h (y = -v here).
    const GridSize grid{3, 61};
    std::vector<Vec3f> positions;
    for (int j = 0; j < grid.nv; ++j)
        for (int i = 0; i < grid.nu; ++i) {
            const double v = double(j) / (grid.nv - 1);
            positions.emplace_back(float(i), float(-v), float(0.05 * std::cos(3.0 * kPi * v)));
        }
    const CentreFibreFolds folds = centre_fibre_folds(positions, grid);
    EXPECT_EQ(folds.sign_changes, 3);
    ASSERT_EQ(folds.crest_heights_m.size(), 4u);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(folds.crest_heights_m[std::size_t(k)], -k / 3.0, 1e-3) << k;
    // The lowest crest is where the fibre runs straight (|dz/dy| <= 0.1): a cosine's flank
    // flattens one row above its extreme.
    EXPECT_NEAR(folds.crest_heights_m[3], -1.0, 1.0 / (grid.nv - 1) + 1e-3);
}

// Below its lowest fold line a fibre hangs straight at about the fold's depth; a run that
// leans a few millimetres further out towards the hem (as a relaxed grid's does) does not
// move the crest down to the hem.
TEST(Relax, LowestCrestIsWhereTheFibreStopsFolding) {
    const GridSize grid{3, 71};
    std::vector<Vec3f> positions;
    for (int j = 0; j < grid.nv; ++j)
        for (int i = 0; i < grid.nu; ++i) {
            // A 0.7 m fibre: one 2.5 cm deep fold over the top 0.15 m, then straight.
            const double v = 0.7 * double(j) / (grid.nv - 1);
            double z = v < 0.15 ? 0.025 * std::cos(kPi * v / 0.15) : -0.025;
            if (v > 0.15) z -= 0.003 * (v - 0.15) / 0.55;  // the straight run leans 3 mm out
            positions.emplace_back(float(i), float(-v), float(z));
        }
    const CentreFibreFolds folds = centre_fibre_folds(positions, grid);
    EXPECT_EQ(folds.sign_changes, 1);
    ASSERT_EQ(folds.crest_heights_m.size(), 2u);
    EXPECT_NEAR(folds.crest_heights_m[0], 0.0, 1e-3);
    EXPECT_NEAR(folds.crest_heights_m[1], -0.15, 0.7 / (grid.nv - 1) + 1e-3);
}

// What animation frames use (frame_settings in animation.cpp): over-relaxed projections and
// strain limiting in windows reach the same bounds as plain projections, in fewer
// iterations, with every pin where it was.  The default garment at 64x64 from its model.
TEST(Relax, OverRelaxationAndWindowsReachTheBoundsSooner) {
    const ClothParams p;
    const GridSize grid{64, 64};
    const Garment model = build_garment(p, solve_folds(p), grid, false);
    const auto run = [&](const RelaxSettings& settings) {
        std::vector<Vec3f> positions = model.mesh.positions;
        const RelaxReport report =
            GridRelaxer(p, grid, model.support_vertices, settings).relax(positions, model.mesh.positions);
        for (const int v : model.support_vertices)
            EXPECT_EQ(positions[std::size_t(v)], model.mesh.positions[std::size_t(v)]) << v;
        return report;
    };
    RelaxSettings plain;
    plain.smoothing_iterations = 0;
    RelaxSettings over = plain, windows = plain;
    over.over_relaxation = 2.0;
    windows.window_fix_below_max = 0.1;
    const RelaxReport slow = run(plain), over_relaxed = run(over), fixed = run(windows);
    for (const RelaxReport& r : {slow, over_relaxed, fixed}) {
        EXPECT_LE(r.after.mean, plain.target_mean);
        EXPECT_LE(r.after.max, plain.target_max);
    }
    EXPECT_LT(over_relaxed.iterations, slow.iterations);
    EXPECT_GT(fixed.window_fixes, 0);
    EXPECT_LT(fixed.iterations, slow.iterations);
}

// A relaxation that does not measure (animation frames) moves the cloth the same way.
TEST(Relax, NotReportingTheStretchChangesNothingElse) {
    const ClothParams p;
    const GridSize grid{24, 32};
    const Garment model = build_garment(p, solve_folds(p), grid, false);
    RelaxSettings quiet;
    quiet.report_stretch = false;
    std::vector<Vec3f> measured = model.mesh.positions, unmeasured = model.mesh.positions;
    const RelaxReport a = GridRelaxer(p, grid, model.support_vertices).relax(measured, model.mesh.positions);
    const RelaxReport b = GridRelaxer(p, grid, model.support_vertices, quiet).relax(unmeasured, model.mesh.positions);
    EXPECT_EQ(measured, unmeasured);
    EXPECT_EQ(a.iterations, b.iterations);
    EXPECT_GT(a.before.mean, 0.0);
    EXPECT_EQ(b.before.mean, 0.0);
    EXPECT_EQ(b.after.max, 0.0);
}

TEST(Relax, RejectsSettingsOutOfRange) {
    const ClothParams p;
    RelaxSettings settings;
    settings.proximal_share = 0.0;
    EXPECT_THROW(GridRelaxer(p, {8, 8}, {0, 7}, settings), InputError);
    settings = {};
    settings.over_relaxation = 2.5;
    EXPECT_THROW(GridRelaxer(p, {8, 8}, {0, 7}, settings), InputError);
}

// A flat sheet does not turn; a quarter cylinder turns by its angle per column between
// neighbouring columns of quads and not at all along its axis, so its 90th percentile is
// that angle.
TEST(Relax, TurnBetweenQuadsMeasuresBending) {
    const GridSize grid{21, 9};
    std::vector<Vec3f> flat, cylinder;
    const double step = 0.5 * kPi / (grid.nu - 1);
    for (int j = 0; j < grid.nv; ++j)
        for (int i = 0; i < grid.nu; ++i) {
            flat.emplace_back(float(0.1 * i), float(-0.1 * j), 0.0f);
            cylinder.emplace_back(float(std::sin(step * i)), float(-0.1 * j), float(std::cos(step * i)));
        }
    EXPECT_EQ(turn_p90(flat, grid), 0.0);
    EXPECT_NEAR(turn_p90(cylinder, grid), step, 1e-4);
    EXPECT_THROW(turn_p90(flat, {20, 9}), InputError);
}

TEST(Relax, RejectsMismatchedInput) {
    const ClothParams p;
    EXPECT_THROW(GridRelaxer(p, {8, 8}, {64}), InputError);
    const GridRelaxer relaxer(p, {8, 8}, {0, 7});
    std::vector<Vec3f> positions(10), targets(64);
    EXPECT_THROW(relaxer.relax(positions, targets), InputError);
}

}  // namespace
}  // namespace foldcast::drape

namespace foldcast::drape {
namespace {

// The hem measures: a flat sheet's hem is as wide as the cloth and level; the model's garment
// hangs its hem within the support span, its centre lifted above its corners (the hem closure).
TEST(HemShape, FlatSheetAndTheModelsGarment) {
    const GridSize grid{9, 5};
    std::vector<Vec3f> flat;
    for (int j = 0; j < grid.nv; ++j)
        for (int i = 0; i < grid.nu; ++i) flat.emplace_back(-0.25f + 0.5f * i / 8.0f, -0.7f * j / 4.0f, 0.0f);
    const HemShape sheet = hem_shape(flat, grid);
    EXPECT_NEAR(sheet.width_m, 0.5, 1e-6);
    EXPECT_NEAR(sheet.centre_y_m, -0.7, 1e-6);
    EXPECT_NEAR(sheet.corners_y_m, -0.7, 1e-6);
    EXPECT_THROW(hem_shape(flat, {9, 4}), InputError);

    const ClothParams p;
    const Garment model = build_garment(p, solve_folds(p), {33, 33}, false);
    const HemShape hem = hem_shape(model.mesh.positions, {33, 33});
    EXPECT_NEAR(hem.width_m, p.support_span_m(), 0.01);
    EXPECT_GT(hem.centre_y_m, hem.corners_y_m + 0.05);
}

}  // namespace
}  // namespace foldcast::drape
