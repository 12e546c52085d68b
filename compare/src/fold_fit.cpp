// The search of the model's physical parameters for the best agreement with a photo.
#include <algorithm>
#include <cmath>

#include "foldcast/compare/overlay.hpp"

namespace foldcast::compare {
namespace {

void check_bounds(const FitBounds& b) {
    auto fail = [](const std::string& what) { throw InputError("fit bounds: " + what); };
    if (!(std::isfinite(b.inset_min_m) && std::isfinite(b.inset_max_m) && b.inset_min_m >= 0 &&
          b.inset_max_m >= b.inset_min_m))
        fail("inset range [" + std::to_string(b.inset_min_m) + ", " + std::to_string(b.inset_max_m) +
             "] m must be finite with 0 <= min <= max");
    if (!(std::isfinite(b.young_min_pa) && std::isfinite(b.young_max_pa) && b.young_min_pa > 0 &&
          b.young_max_pa >= b.young_min_pa))
        fail("Young's modulus range [" + std::to_string(b.young_min_pa) + ", " + std::to_string(b.young_max_pa) +
             "] Pa must be finite with 0 < min <= max");
    if (b.inset_steps < 1 || b.young_steps < 1 || b.inset_steps > 200 || b.young_steps > 200)
        fail("steps must be 1 to 200 (inset " + std::to_string(b.inset_steps) + ", E " + std::to_string(b.young_steps) +
             ")");
}

double step_value(double lo, double hi, int i, int steps, bool log_spaced) {
    if (steps == 1) return lo;
    const double t = double(i) / (steps - 1);
    return log_spaced ? lo * std::pow(hi / lo, t) : lo + (hi - lo) * t;
}

// How far a set lies from the start, each axis as a share of its box (E on a log scale).
double distance_from_start(const drape::ClothParams& p, const drape::ClothParams& start, const FitBounds& b) {
    const double inset_span = b.inset_max_m - b.inset_min_m;
    const double young_span = std::log(b.young_max_pa / b.young_min_pa);
    const double di = inset_span > 0 ? (p.inset_m - start.inset_m) / inset_span : 0.0;
    const double dy = young_span > 0 ? std::log(p.young_pa / start.young_pa) / young_span : 0.0;
    return std::hypot(di, dy);
}

}  // namespace

FitResult fit_folds(const drape::ClothParams& start, const FitBounds& bounds, const GeometryFn& geometry_for,
                    const std::function<ClothToImage(const drape::ClothParams&)>& map_for, const Image& mask,
                    const FoldDetection& detection, const CentreLine& centre, double tolerance_px) {
    check_bounds(bounds);
    struct Tried {
        double inset_m, young_pa, agreement;
    };
    std::vector<Tried> tried;
    FitResult best;
    const bool measured = centre.folds > 0 && !centre.depths_px.empty();
    ModelReach reach;
    reach.folds = centre.folds;
    if (measured) reach.measured_px = centre.depths_px.back();
    bool have = false;
    double best_chamfer_px = 0.0, best_from_start = 0.0;
    for (int i = 0; i < bounds.inset_steps; ++i)
        for (int j = 0; j < bounds.young_steps; ++j) {
            drape::ClothParams p = start;
            p.inset_m = step_value(bounds.inset_min_m, bounds.inset_max_m, i, bounds.inset_steps, false);
            p.young_pa = step_value(bounds.young_min_pa, bounds.young_max_pa, j, bounds.young_steps, true);
            drape::FoldSolution solution;
            ClothToImage map;
            try {
                if (geometry_for) p = geometry_for(p);
                drape::validate(p);
                solution = drape::solve_folds(p);
                map = map_for(p);
            } catch (const InputError&) {
                continue;  // outside the model's valid range (the inset leaves no span)
            }
            if (measured && solution.folds == centre.folds && !solution.amplitudes_m.empty()) {
                // The lowest fold line crosses the centre fibre at (0, -a_0) in the cloth plane.
                const double depth = (map(0.0, -solution.amplitudes_m.front()) - map(0.0, 0.0)).norm();
                reach.lowest_min_px = reach.sets ? std::min(reach.lowest_min_px, depth) : depth;
                reach.lowest_max_px = reach.sets ? std::max(reach.lowest_max_px, depth) : depth;
                ++reach.sets;
            }
            const auto lines =
                clip_to_cloth(project_fold_lines(drape::fold_lines(p, solution), solution.folds, map), mask);
            FoldScore score = score_folds(lines, detection, centre, map.px_per_m, tolerance_px);
            // Sets the model solves without folds draw nothing; their n is still compared.
            score.predicted_folds = solution.folds;
            score.count_error = solution.folds - centre.folds;
            score.agreement = agreement(score.f1, score.count_error);
            tried.push_back({p.inset_m, p.young_pa, score.agreement});
            ++best.evaluated;
            const double chamfer_px = score.chamfer_cm * score.tolerance_px / score.tolerance_cm;
            const double from_start = distance_from_start(p, start, bounds);
            bool better = !have || score.agreement > best.score.agreement + 1e-12;
            if (have && std::abs(score.agreement - best.score.agreement) <= 1e-12) {
                if (chamfer_px < best_chamfer_px - 1e-6)
                    better = true;
                else if (std::abs(chamfer_px - best_chamfer_px) <= 1e-6 && from_start < best_from_start)
                    better = true;
            }
            if (better) {
                best_chamfer_px = chamfer_px;
                best_from_start = from_start;
                best.params = p;
                best.solution = solution;
                best.score = score;
                have = true;
            }
        }
    if (!have)
        throw InputError("fit: no parameter set in the search box (inset " + std::to_string(bounds.inset_min_m) +
                         " to " + std::to_string(bounds.inset_max_m) + " m) could be solved");
    if (measured) {
        reach.outside = reach.sets == 0 || reach.measured_px < reach.lowest_min_px - tolerance_px ||
                        reach.measured_px > reach.lowest_max_px + tolerance_px;
        best.reach = reach;
    }
    // Uncertainty: every set within 5 % of the best agreement.
    const double near = 0.95 * best.score.agreement;
    best.nothing_matched = best.score.f1 <= 0.0;
    auto range = [&](double Tried::*field, double best_value, double lo, double hi) {
        FittedValue v;
        v.best = best_value;
        v.low = best_value;
        v.high = best_value;
        v.bound_min = lo;
        v.bound_max = hi;
        for (const auto& t : tried)
            if (t.agreement >= near) {
                v.low = std::min(v.low, t.*field);
                v.high = std::max(v.high, t.*field);
            }
        const double eps = 1e-9 * std::max(1.0, std::abs(hi));
        v.on_bound = hi > lo && (std::abs(best_value - lo) <= eps || std::abs(best_value - hi) <= eps);
        v.constrained = !(hi > lo && v.low <= lo + eps && v.high >= hi - eps);
        return v;
    };
    best.inset_m = range(&Tried::inset_m, best.params.inset_m, bounds.inset_min_m, bounds.inset_max_m);
    best.young_pa = range(&Tried::young_pa, best.params.young_pa, bounds.young_min_pa, bounds.young_max_pa);
    return best;
}

}  // namespace foldcast::compare
