// Physical trends the model must show over realistic fabric ranges (docs/drape.md):
// more folds for taller, heavier, thinner or softer cloth; deeper folds with more slack.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "foldcast/drape/drape.hpp"

namespace foldcast::drape {
namespace monotonic_test {

struct Fabric {
    double thickness_mm, young_mpa, gsm, height_m;
};
// A light shirting, a medium cotton and a heavy denim-like cloth.
const std::vector<Fabric> kBases = {{0.15, 3.0, 90.0, 0.7}, {0.3, 5.0, 150.0, 0.7}, {0.6, 20.0, 350.0, 1.0}};

ClothParams params(const Fabric& f) {
    looks::Mechanics m;
    m.thickness_mm = f.thickness_mm;
    m.young_mpa = f.young_mpa;
    m.gsm = f.gsm;
    return cloth_from_look(m, 0.5, f.height_m, 0.1);
}

std::vector<double> geometric(double from, double to, int count) {
    std::vector<double> v;
    for (int i = 0; i < count; ++i) v.push_back(from * std::pow(to / from, double(i) / (count - 1)));
    return v;
}

// Fold counts along a sweep of one parameter, for each base fabric.
void expect_monotone(const std::vector<double>& values, const std::function<void(Fabric&, double)>& set,
                     bool increasing, const char* what) {
    for (const Fabric& base : kBases) {
        int previous = increasing ? 0 : 1 << 30;
        int first = -1, last = -1;
        for (double value : values) {
            Fabric f = base;
            set(f, value);
            const FoldSolution s = solve_folds(params(f));
            // The hem closure answers for every cloth that buckles (closure_test.cpp).
            EXPECT_NE(s.regime, FoldSolution::Regime::no_feasible_folds) << what << " = " << value;
            const int n = s.folds;
            if (first < 0) first = n;
            last = n;
            if (increasing)
                EXPECT_GE(n, previous) << what << " = " << value << " (base t=" << base.thickness_mm << " mm)";
            else
                EXPECT_LE(n, previous) << what << " = " << value << " (base t=" << base.thickness_mm << " mm)";
            previous = n;
        }
        // The sweep must actually change the answer, or the test proves nothing.
        EXPECT_NE(first, last) << what << " (base t=" << base.thickness_mm << " mm)";
    }
}

TEST(Monotonic, MoreFoldsForTallerCloth) {
    expect_monotone(
        geometric(0.3, 1.5, 25), [](Fabric& f, double v) { f.height_m = v; }, true, "height_m");
}
TEST(Monotonic, MoreFoldsForHeavierCloth) {
    expect_monotone(
        geometric(50, 400, 25), [](Fabric& f, double v) { f.gsm = v; }, true, "gsm");
}
TEST(Monotonic, FewerFoldsForThickerCloth) {
    expect_monotone(
        geometric(0.1, 1.0, 25), [](Fabric& f, double v) { f.thickness_mm = v; }, false, "thickness_mm");
}
TEST(Monotonic, FewerFoldsForStifferCloth) {
    expect_monotone(
        geometric(1, 50, 25), [](Fabric& f, double v) { f.young_mpa = v; }, false, "young_mpa");
}

// Slack L - l with the support span l fixed (so Q is fixed): the folds get fewer and deeper.
// Within a run of constant n the extra slack goes mostly into the sag a_n and zmax dips a
// little (docs/drape.md), so depth is compared as the deepest fold in each octave of slack.
TEST(Monotonic, DeeperFoldsWithMoreSlack) {
    for (const Fabric& base : kBases) {
        const auto solve = [&](double slack) {
            ClothParams p = params(base);
            p.inset_m = 0.5 * slack;
            p.width_m = 0.3 + slack;
            return solve_folds(p);
        };
        int previous_n = 1 << 30;
        double previous_octave_depth = 0.0;
        int octaves = 0;
        for (double octave = 0.01; octave < 0.6; octave *= 2.0) {
            double depth = 0.0;
            for (double slack : geometric(octave, 2.0 * octave, 8)) {
                const FoldSolution s = solve(slack);
                if (s.regime != FoldSolution::Regime::wrinkled) continue;
                EXPECT_LE(s.folds, previous_n) << "slack " << slack;
                previous_n = s.folds;
                depth = std::max(depth, s.zmax_m);
            }
            if (depth == 0.0) continue;
            EXPECT_GT(depth, previous_octave_depth) << "octave from slack " << octave;
            previous_octave_depth = depth;
            ++octaves;
        }
        EXPECT_GE(octaves, 4) << "base t=" << base.thickness_mm << " mm";
    }
}

}  // namespace monotonic_test
}  // namespace foldcast::drape
