// The score, the centre-line measurement, the fit and the photo pipeline on synthetic photos
// drawn from the model: the cloth (its top edge sagging as the model's) with bright crests
// and dark valleys along the projected fold lines.  What is known here is the truth the
// picture was drawn from; the tests check that the measurement finds it and that the score
// and fit prefer it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "compare_test_util.hpp"
#include "foldcast/core/math.hpp"
#include "foldcast/compare/photo_overlay.hpp"
#include "test_paths.hpp"

using namespace foldcast;
using foldcast::test::constant_image;

namespace {

struct Synthetic {
    drape::ClothParams params;
    drape::FoldSolution solution;
    compare::SupportPixels supports;
    compare::ClothToImage map;
    std::vector<compare::PredictedLine> lines;  // projected, top edge included
    compare::Image photo, mask;
};

double distance_to_polyline(const std::vector<Eigen::Vector2d>& pts, const Eigen::Vector2d& q) {
    double d = 1e9;
    for (size_t i = 1; i < pts.size(); ++i) {
        const Eigen::Vector2d a = pts[i - 1], b = pts[i];
        const double t = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
        d = std::min(d, (a + t * (b - a) - q).norm());
    }
    return d;
}

// A 0.5 x 0.45 m cloth at 700 px/m: supports 700 (W - 2d) px apart, 60 px from the top.
Synthetic make_synthetic(double inset_m, double young_pa) {
    Synthetic s;
    s.params.width_m = 0.5;
    s.params.height_m = 0.45;
    s.params.inset_m = inset_m;
    s.params.young_pa = young_pa;
    s.solution = drape::solve_folds(s.params);
    const double px_per_m = 700.0, span_px = px_per_m * s.params.support_span_m();
    const int w = static_cast<int>(std::ceil(span_px + 160)),
              h = static_cast<int>(std::ceil(60 + px_per_m * 0.45 + 60));
    s.supports = {{80, 60}, {80 + span_px, 60}};
    s.map = compare::similarity_from_supports(s.supports, s.params.support_span_m());
    s.lines = compare::project_fold_lines(drape::fold_lines(s.params, s.solution, 257), s.solution.folds, s.map);
    // The cloth: between the supports below the sagging top edge (a_n cos), down to the hem.
    const double a_top_px = s.solution.folds > 0 ? px_per_m * s.solution.amplitudes_m.back() : 0.0;
    s.mask = constant_image(w, h, 1, 0.0f);
    s.photo = constant_image(w, h, 3, 0.9f);  // light background
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double u = (x - s.supports.first.x()) / span_px - 0.5;  // -0.5 .. 0.5 between the supports
            if (std::abs(u) > 0.5) continue;
            const double top = 60 + a_top_px * std::cos(kPi * u);
            if (y < top || y > 60 + px_per_m * s.params.height_m) continue;
            s.mask.at(x, y, 0) = 1.0f;
            double v = 0.35;
            for (const auto& l : s.lines) {
                if (l.top_edge) continue;
                const double d = distance_to_polyline(l.points_px, Eigen::Vector2d(x, y));
                v += 0.15 * l.sign * std::exp(-d * d / (2 * 2.0 * 2.0));
            }
            for (int c = 0; c < 3; ++c) s.photo.at(x, y, c) = static_cast<float>(v);
        }
    return s;
}

const Synthetic& synthetic() {
    static const Synthetic s = make_synthetic(0.1, 5e6);
    return s;
}

// The fit's search box: `inset_steps` insets in [inset_min, inset_max] m and `young_steps`
// moduli in [young_min, young_max] Pa.
compare::FitBounds box(double inset_min, double inset_max, int inset_steps, double young_min, double young_max,
                       int young_steps) {
    compare::FitBounds b;
    b.inset_min_m = inset_min, b.inset_max_m = inset_max, b.inset_steps = inset_steps;
    b.young_min_pa = young_min, b.young_max_pa = young_max, b.young_steps = young_steps;
    return b;
}

// fit_folds on the synthetic photo, its pixel map from the supports for every set tried.
compare::FitResult fit_synthetic(const Synthetic& s, const drape::ClothParams& start, const compare::FitBounds& bounds,
                                 const compare::FoldDetection& detection, const compare::CentreLine& centre,
                                 double tolerance_px) {
    const auto map_for = [&](const drape::ClothParams& p) {
        return compare::similarity_from_supports(s.supports, p.support_span_m());
    };
    return compare::fit_folds(start, bounds, {}, map_for, s.mask, detection, centre, tolerance_px);
}

}  // namespace

TEST(CentreLine, MeasuresTheFoldCountAndQDrawnFromTheModel) {
    const auto& s = synthetic();
    ASSERT_GE(s.solution.folds, 1);
    const auto detection = compare::detect_folds(s.photo, s.mask);
    const auto centre = compare::measure_centre_line(detection, s.supports);
    EXPECT_EQ(centre.folds, s.solution.folds);
    ASSERT_TRUE(centre.Q.has_value());
    EXPECT_NEAR(*centre.Q, s.solution.Q, 0.1 * s.solution.Q);
    // Each measured depth lies within 2 px of a model fold line's depth at the centre.
    for (size_t k = 0; k < centre.depths_px.size(); ++k) {
        double best = 1e9;
        for (int i = 0; i < s.solution.folds; ++i)
            best = std::min(best, std::abs(centre.depths_px[k] - s.map.px_per_m * s.solution.amplitudes_m[size_t(i)]));
        EXPECT_LT(best, 2.0) << "depth " << centre.depths_px[k];
    }
    // A flat cloth has no folds on its centre line.
    compare::Image flat = s.photo;
    for (int y = 0; y < flat.height; ++y)
        for (int x = 0; x < flat.width; ++x)
            if (s.mask.at(x, y, 0) > 0.5f)
                for (int c = 0; c < 3; ++c) flat.at(x, y, c) = 0.35f;
    EXPECT_EQ(compare::measure_centre_line(compare::detect_folds(flat, s.mask), s.supports).folds, 0);
}

// As the 2-D detector's hysteresis: with the high threshold raised above every fold's
// strength on the fibre (as glossy cloth's highlights raise it), a fold still counts where a
// detected line of its sign crosses the fibre and it clears the low threshold; without the
// lines, it does not.  Each threshold is raised with its floor (on this clean picture the
// floor, on the luma's response, is what binds).
TEST(CentreLine, FoldsUnderTheHighThresholdCountWhereADetectedLineCrossesTheFibre) {
    const auto& s = synthetic();
    compare::FoldDetection detection = compare::detect_folds(s.photo, s.mask);
    ASSERT_FALSE(detection.folds.empty());
    const int seen = compare::measure_centre_line(detection, s.supports).folds;
    ASSERT_EQ(seen, s.solution.folds);
    detection.high_threshold *= 100.0, detection.high_floor *= 100.0;  // no extremum on the fibre reaches them
    EXPECT_EQ(compare::measure_centre_line(detection, s.supports).folds, seen);
    detection.low_threshold *= 100.0, detection.low_floor *= 100.0;  // nor the low ones now
    EXPECT_EQ(compare::measure_centre_line(detection, s.supports).folds, 0);
    detection.low_threshold /= 100.0, detection.low_floor /= 100.0;
    detection.folds.clear();  // no line crosses the fibre
    EXPECT_EQ(compare::measure_centre_line(detection, s.supports).folds, 0);
}

// Photo noise does not add folds: extrema are kept one per twice their own scale apart (not
// the largest scale's), so pixel noise on the fibre must not pass for folds.
TEST(CentreLine, NoiseOnThePhotoAddsNoFolds) {
    const auto& s = synthetic();
    for (const float amplitude : {0.03f, 0.1f}) {
        compare::Image noisy = s.photo;
        std::uint32_t state = 12345u;
        for (float& v : noisy.values) {
            state = state * 1664525u + 1013904223u;  // a fixed LCG: the same noise every run
            v = std::clamp(v + amplitude * (float(state >> 8) / float(1u << 24) - 0.5f) * 2.0f, 0.0f, 1.0f);
        }
        const auto centre = compare::measure_centre_line(compare::detect_folds(noisy, s.mask), s.supports);
        EXPECT_EQ(centre.folds, s.solution.folds) << "noise amplitude " << amplitude;
    }
}

// A fold changes the light a patch of cloth gets by a ratio, so the same drape on a darker
// cloth (the photo, its noise included, at half the brightness) shows the same folds: on the
// relative shading the ridge filter reads, they respond as strongly and the threshold (4 x the
// cloth's median response) is the same.  On the luma itself both halved with the cloth's
// albedo, and a dark cloth's folds fell under the floor of the threshold first.
TEST(CentreLine, ADarkerClothMeasuresTheSameFoldsAtTheSameStrength) {
    const auto& s = synthetic();
    compare::Image light = s.photo;
    std::uint32_t state = 12345u;
    for (float& v : light.values) {
        state = state * 1664525u + 1013904223u;
        v = std::clamp(v + 0.03f * (float(state >> 8) / float(1u << 24) - 0.5f) * 2.0f, 0.0f, 1.0f);
    }
    compare::Image dark = light;
    for (float& v : dark.values) v *= 0.5f;
    const auto a = compare::detect_folds(light, s.mask), b = compare::detect_folds(dark, s.mask);
    EXPECT_NEAR(b.high_threshold, a.high_threshold, 1e-3 * a.high_threshold);
    ASSERT_FALSE(a.folds.empty());
    ASSERT_EQ(b.folds.size(), a.folds.size());
    for (size_t k = 0; k < a.folds.size(); ++k)
        EXPECT_NEAR(b.folds[k].mean_strength, a.folds[k].mean_strength, 1e-3 * a.folds[k].mean_strength) << k;
    const auto centre_light = compare::measure_centre_line(a, s.supports);
    const auto centre_dark = compare::measure_centre_line(b, s.supports);
    EXPECT_EQ(centre_light.folds, s.solution.folds);
    EXPECT_EQ(centre_dark.folds, centre_light.folds);
    EXPECT_EQ(centre_dark.depths_px, centre_light.depths_px);
}

TEST(OverlayScore, ThreeTimesTheVisibleFoldsScoresWorseThanTheRightCount) {
    const auto& s = synthetic();
    const auto detection = compare::detect_folds(s.photo, s.mask);
    const auto centre = compare::measure_centre_line(detection, s.supports);
    const auto right = compare::clip_to_cloth(s.lines, s.mask);
    // Three times the folds: two more lines of the same family between each pair of the model's
    // lines (and between the top edge and the highest fold), signs alternating.
    std::vector<compare::PredictedLine> dense;
    std::vector<compare::PredictedLine> all = s.lines;
    for (size_t i = 0; i + 1 < all.size(); ++i) {
        compare::PredictedLine a = all[i];
        a.top_edge = false;
        dense.push_back(a);
        for (int k = 1; k <= 2; ++k) {
            compare::PredictedLine mid{int(dense.size()), dense.size() % 2 == 0 ? 1 : -1, false, {}};
            for (size_t j = 0; j < all[i].points_px.size(); ++j)
                mid.points_px.push_back(all[i].points_px[j] +
                                        (all[i + 1].points_px[j] - all[i].points_px[j]) * (k / 3.0));
            dense.push_back(mid);
        }
    }
    for (size_t i = 0; i < dense.size(); ++i) dense[i].index = int(i);
    const auto dense_clipped = compare::clip_to_cloth(dense, s.mask);
    const double tol = 0.02 * s.supports.distance_px();
    const auto good = compare::score_folds(right, detection, centre, s.map.px_per_m, tol);
    const auto bad = compare::score_folds(dense_clipped, detection, centre, s.map.px_per_m, tol);
    EXPECT_EQ(good.count_error, 0);
    EXPECT_EQ(bad.predicted_folds, 3 * s.solution.folds);
    EXPECT_GT(good.precision, 0.9);
    EXPECT_LT(bad.precision, 0.7 * good.precision);  // most of the extra length lies on no fold
    EXPECT_LT(bad.f1, good.f1);
    EXPECT_LT(bad.agreement, good.agreement - 0.2);
    // And an empty prediction scores zero.
    EXPECT_EQ(compare::score_folds({}, detection, centre, s.map.px_per_m, tol).f1, 0.0);
    EXPECT_THROW(compare::score_folds(right, detection, centre, s.map.px_per_m, NAN), InputError);
}

TEST(OverlayClip, NothingIsDrawnOutsideTheCloth) {
    const auto& s = synthetic();
    // A mask that only holds the left half of the cloth.
    compare::Image half = s.mask;
    for (int y = 0; y < half.height; ++y)
        for (int x = half.width / 2; x < half.width; ++x) half.at(x, y, 0) = 0.0f;
    const auto clipped = compare::clip_to_cloth(s.lines, half);
    ASSERT_FALSE(clipped.empty());
    for (const auto& l : clipped) {
        EXPECT_FALSE(l.top_edge);
        for (const auto& p : l.points_px) {
            const int x = int(std::lround(p.x())), y = int(std::lround(p.y()));
            ASSERT_TRUE(x >= 0 && y >= 0 && x < half.width && y < half.height);
            EXPECT_EQ(half.at(x, y, 0), 1.0f) << p.transpose();
        }
    }
}

TEST(OverlayFit, AScoreFlatOverTheWholeBoxIsReportedNotDecidedAndTheStartIsKept) {
    // No detected line and the measured n equal to the model's: every set in a narrow box
    // (the same n throughout) scores the same, so neither value is decided by the photo, and
    // the tie goes to the start (the physical default), the middle of the grid.
    const auto& s = synthetic();
    auto detection = compare::detect_folds(s.photo, s.mask);
    detection.folds.clear();
    compare::CentreLine centre;
    centre.folds = s.solution.folds;
    const compare::FitBounds bounds = box(0.098, 0.102, 5, s.params.young_pa / 1.02, s.params.young_pa * 1.02, 5);
    const auto fit = fit_synthetic(s, s.params, bounds, detection, centre, 0.02 * s.supports.distance_px());
    ASSERT_EQ(fit.solution.folds, s.solution.folds);
    EXPECT_DOUBLE_EQ(fit.score.agreement, 0.5);  // F1 0, count error 0
    EXPECT_FALSE(fit.inset_m.constrained);
    EXPECT_FALSE(fit.young_pa.constrained);
    EXPECT_NEAR(fit.params.inset_m, 0.1, 1e-9);
    EXPECT_NEAR(fit.params.young_pa, s.params.young_pa, 1e-6 * s.params.young_pa);
}

TEST(OverlayFit, FindsTheFoldCountAndInsetTheSyntheticPhotoWasDrawnWith) {
    // Drawn with inset 0.1 m and E 5 MPa; the fit starts from 3x too stiff a fabric.
    const auto& s = synthetic();
    const auto detection = compare::detect_folds(s.photo, s.mask);
    const auto centre = compare::measure_centre_line(detection, s.supports);
    drape::ClothParams start = s.params;
    start.young_pa = 15e6;
    start.inset_m = 0.05;
    // 0.025 m steps of the inset: 0.1 is on the grid.
    compare::FitBounds bounds = box(0.0, 0.2, 9, start.young_pa / 10, start.young_pa * 10, 9);
    const auto fit = fit_synthetic(s, start, bounds, detection, centre, 0.02 * s.supports.distance_px());
    EXPECT_EQ(fit.solution.folds, s.solution.folds);
    EXPECT_NEAR(fit.params.inset_m, 0.1, 0.0251);
    EXPECT_LE(fit.inset_m.low, 0.1 + 1e-9);
    EXPECT_GE(fit.inset_m.high, 0.1 - 0.0251);
    EXPECT_FALSE(fit.nothing_matched);
    EXPECT_FALSE(fit.inset_m.on_bound);
    EXPECT_TRUE(fit.inset_m.constrained);  // the photo decides the inset (the check below can fail)
    EXPECT_GT(fit.score.f1, 0.7);
    EXPECT_LE(fit.young_pa.low, fit.young_pa.best);
    EXPECT_GE(fit.young_pa.high, fit.young_pa.best);
    // A box that stops short of the true inset (0.1 m) fits worse, and its report says
    // whether its best lies on a bound exactly when it does.
    bounds.inset_min_m = 0.0;
    bounds.inset_max_m = 0.05;
    bounds.inset_steps = 3;
    const auto edge = fit_synthetic(s, start, bounds, detection, centre, 0.02 * s.supports.distance_px());
    EXPECT_LT(edge.score.agreement, fit.score.agreement);
    const bool at_bound = std::abs(edge.params.inset_m - bounds.inset_min_m) < 1e-9 ||
                          std::abs(edge.params.inset_m - bounds.inset_max_m) < 1e-9;
    EXPECT_EQ(edge.inset_m.on_bound, at_bound);
    bounds.young_min_pa = -1;
    EXPECT_THROW(fit_synthetic(s, start, bounds, detection, centre, 2.0), InputError);
}

TEST(OverlayFit, SaysWhenNoSetWithTheMeasuredCountPutsItsFoldWhereThePhotoHasIt) {
    // The photo drawn from the model (inset 0.1 m, E 5 MPa): its measured lowest fold lies
    // within the depths the box's sets with that count draw.  The same count measured far
    // higher (10 px below the supports) lies outside them: the report says the model cannot
    // reach it; a count no set has is outside too.
    const auto& s = synthetic();
    const auto detection = compare::detect_folds(s.photo, s.mask);
    const auto centre = compare::measure_centre_line(detection, s.supports);
    ASSERT_EQ(centre.folds, s.solution.folds);
    const compare::FitBounds bounds = box(0.05, 0.15, 5, s.params.young_pa / 3, s.params.young_pa * 3, 5);
    const double tolerance = 0.02 * s.supports.distance_px();
    const auto fit = fit_synthetic(s, s.params, bounds, detection, centre, tolerance);
    ASSERT_TRUE(fit.reach.has_value());
    EXPECT_EQ(fit.reach->folds, s.solution.folds);
    EXPECT_GT(fit.reach->sets, 0);
    EXPECT_LE(fit.reach->lowest_min_px, fit.reach->lowest_max_px);
    EXPECT_NEAR(fit.reach->measured_px, 700.0 * s.solution.amplitudes_m.front(), 3.0);
    EXPECT_FALSE(fit.reach->outside);

    compare::CentreLine high = centre;
    high.depths_px.back() = 10.0;
    const auto miss = fit_synthetic(s, s.params, bounds, detection, high, tolerance);
    ASSERT_TRUE(miss.reach.has_value());
    EXPECT_LT(miss.reach->measured_px, miss.reach->lowest_min_px - tolerance);
    EXPECT_TRUE(miss.reach->outside);

    compare::CentreLine many = centre;
    many.folds = 60;
    const auto none = fit_synthetic(s, s.params, bounds, detection, many, tolerance);
    ASSERT_TRUE(none.reach.has_value());
    EXPECT_EQ(none.reach->sets, 0);
    EXPECT_TRUE(none.reach->outside);

    compare::CentreLine flat;  // nothing measured: nothing to reach
    EXPECT_FALSE(fit_synthetic(s, s.params, bounds, detection, flat, tolerance).reach);
}

TEST(PhotoOverlay, GeometryFromTheMaskLinesOnTheClothAndErrors) {
    const auto& s = synthetic();
    compare::OverlayRequest r;
    r.supports = s.supports;
    r.look_name = "test";
    r.mechanics.thickness_mm = 0.3;
    r.mechanics.young_mpa = 5.0;
    r.mechanics.gsm = 1.47 / 9.80665 * 1e3;
    r.mask = s.mask;
    r.width_m = 0.5;
    r.inset_m = 0.1;
    r.score = true;
    const auto result = compare::overlay_photo(s.photo, r);
    // The height comes from the mask: 0.45 m within 2 px.
    EXPECT_NEAR(result.params.height_m, 0.45, 2.0 / 700.0);
    EXPECT_NEAR(result.map.px_per_m, 700.0, 1e-6);
    EXPECT_EQ(result.solution.folds, s.solution.folds);
    ASSERT_TRUE(result.score.has_value());
    EXPECT_EQ(result.score->count_error, 0);
    for (const auto& l : result.lines)
        for (const auto& p : l.points_px)
            EXPECT_EQ(s.mask.at(int(std::lround(p.x())), int(std::lround(p.y())), 0), 1.0f);
    EXPECT_EQ(result.picture.width, s.photo.width);
    // The legend sits off the cloth: on a photo with room beside the cloth, drawn without
    // lines, the picture changes no cloth pixel away from the support rings.
    const int wide = s.photo.width + 500;
    compare::Image photo_wide = constant_image(wide, s.photo.height, 3, 0.9f),
                   mask_wide = constant_image(wide, s.photo.height, 1, 0.0f);
    for (int y = 0; y < s.photo.height; ++y)
        for (int x = 0; x < s.photo.width; ++x) {
            mask_wide.at(x, y, 0) = s.mask.at(x, y, 0);
            for (int c = 0; c < 3; ++c) photo_wide.at(x, y, c) = s.photo.at(x, y, c);
        }
    const auto legend_only = compare::draw_overlay(photo_wide, {}, s.supports, result.legend, mask_wide);
    int cloth_changed = 0;
    for (int y = 0; y < s.photo.height; ++y)
        for (int x = 0; x < s.photo.width; ++x) {
            const Eigen::Vector2d q(x, y);
            if (s.mask.at(x, y, 0) < 0.5f || (q - s.supports.first).norm() < 25 || (q - s.supports.second).norm() < 25)
                continue;
            cloth_changed += std::abs(legend_only.at(x, y, 0) - s.photo.at(x, y, 0)) > 0.01f;
        }
    EXPECT_EQ(cloth_changed, 0) << "legend over the cloth";

    // Errors: an empty mask, supports on top of each other or outside, a bad tolerance.
    compare::OverlayRequest bad = r;
    bad.mask = constant_image(s.photo.width, s.photo.height, 1, 0.0f);
    EXPECT_THROW(compare::overlay_photo(s.photo, bad), InputError);
    bad = r;
    bad.supports.second = bad.supports.first;
    EXPECT_THROW(compare::overlay_photo(s.photo, bad), InputError);
    bad = r;
    bad.supports.second = {s.photo.width + 5.0, 60};
    EXPECT_THROW(compare::overlay_photo(s.photo, bad), InputError);
    for (double t : {-1.0, 0.0, double(NAN), double(INFINITY)}) {
        bad = r;
        bad.tolerance = t;
        EXPECT_THROW(compare::overlay_photo(s.photo, bad), InputError) << t;
    }
}

namespace {

// The synthetic photo and mask with `left` and `right` px of background added at the sides.
struct Framed {
    compare::Image photo, mask;
    compare::SupportPixels supports;
};
Framed framed(const Synthetic& s, int left, int right) {
    Framed f;
    const int w = s.photo.width + left + right, h = s.photo.height;
    f.photo = constant_image(w, h, 3, 0.9f);
    f.mask = constant_image(w, h, 1, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < s.photo.width; ++x) {
            f.mask.at(x + left, y, 0) = s.mask.at(x, y, 0);
            for (int c = 0; c < 3; ++c) f.photo.at(x + left, y, c) = s.photo.at(x, y, c);
        }
    f.supports = {s.supports.first + Eigen::Vector2d(left, 0), s.supports.second + Eigen::Vector2d(left, 0)};
    return f;
}

// Cloth pixels under the legend's box (the photo lies at the picture's top left).
int cloth_under(const compare::LegendLayout& l, const compare::Image& mask) {
    int n = 0;
    for (int y = std::max(0, l.y); y < std::min(mask.height, l.y + l.height); ++y)
        for (int x = std::max(0, l.x); x < std::min(mask.width, l.x + l.width); ++x) n += mask.at(x, y, 0) > 0.5f;
    return n;
}

// Cloth pixels the picture changed, away from the support rings (drawn without fold lines).
int cloth_changed(const compare::Image& picture, const Framed& f) {
    int n = 0;
    for (int y = 0; y < f.photo.height; ++y)
        for (int x = 0; x < f.photo.width; ++x) {
            const Eigen::Vector2d q(x, y);
            if (f.mask.at(x, y, 0) < 0.5f || (q - f.supports.first).norm() < 25 || (q - f.supports.second).norm() < 25)
                continue;
            n += std::abs(picture.at(x, y, 0) - f.photo.at(x, y, 0)) > 0.01f;
        }
    return n;
}

}  // namespace

TEST(OverlayLegend, NeverCoversTheClothAtASmallSizeOrBesideAnEdge) {
    // The legend of a real run, on the 370 x 435 synthetic photo: the cloth fills its middle
    // with 80 px beside it, too narrow for the box (the old placement put it over the cloth).
    const auto& s = synthetic();
    compare::OverlayRequest r;
    r.supports = s.supports;
    r.look_name = "test";
    r.mechanics.young_mpa = 5.0;
    r.mask = s.mask;
    r.width_m = 0.5;
    r.inset_m = 0.1;
    r.score = true;
    const auto result = compare::overlay_photo(s.photo, r);
    ASSERT_GE(result.legend.size(), 3u);
    EXPECT_EQ(cloth_under(result.legend_layout, s.mask), 0);
    EXPECT_EQ(result.picture.width, result.legend_layout.picture_width);
    EXPECT_EQ(result.picture.height, result.legend_layout.picture_height);

    // Cloth in the middle, at the left edge and at the right edge of the frame.
    for (const auto& [left, right] : {std::pair{0, 0}, std::pair{0, 420}, std::pair{420, 0}}) {
        const Framed f = framed(s, left, right);
        const auto layout =
            compare::layout_legend(result.legend, f.photo.width, f.photo.height, f.mask, {}, f.supports);
        const auto picture = compare::draw_overlay(f.photo, {}, f.supports, result.legend, f.mask);
        EXPECT_EQ(cloth_under(layout, f.mask), 0) << left << " " << right;
        EXPECT_EQ(cloth_changed(picture, f), 0) << left << " " << right;
        EXPECT_GE(layout.font_scale, compare::kLegendMinFontScale);
        // Every legend line inside the picture.
        EXPECT_GE(layout.x, 0);
        EXPECT_GE(layout.y, 0);
        EXPECT_LE(layout.x + layout.width, picture.width);
        EXPECT_LE(layout.y + layout.height, picture.height);
        if (left == right) {
            // No clear place on the photo: a band, the photo kept whole at the top left.
            EXPECT_NE(layout.place, compare::LegendLayout::Place::photo);
            EXPECT_GT(picture.width * picture.height, f.photo.width * f.photo.height);
        } else {
            // Room beside the cloth: on the photo, on that side.
            EXPECT_EQ(layout.place, compare::LegendLayout::Place::photo);
            EXPECT_EQ(picture.width, f.photo.width);
            if (left > 0)
                EXPECT_LE(layout.x + layout.width, f.supports.first.x()) << layout.x;
            else
                EXPECT_GE(layout.x, f.supports.second.x()) << layout.x;
        }
    }
}

TEST(PhotoOverlay, WithoutASizeTheWidthIsAssumedAndTheInsetMeasured) {
    const auto& s = synthetic();
    compare::OverlayRequest r;
    r.supports = s.supports;
    r.mechanics.young_mpa = 5.0;
    r.mask = s.mask;
    const auto result = compare::overlay_photo(s.photo, r);
    EXPECT_NEAR(result.params.width_m, compare::kAssumedWidthM, 1e-12);
    // The synthetic cloth reaches no further than the supports: inset 0 measured (within a pixel).
    EXPECT_LT(result.params.inset_m, 2.0 / result.map.px_per_m);
    EXPECT_FALSE(result.assumptions.empty());
}

TEST(OverlayCli, InvalidTolerancesAndLengthsExitTwo) {
    const auto dir = test::temp_dir();
    const std::string photo = test::quoted(test::test_data("photos/two_point_shirt_s5_half.jpg"));
    const std::string out = test::quoted(dir / "o.png");
    const std::string overlay = test::foldcast_binary() + " overlay " + photo + " -o " + out +
                                " --supports 197.5,50,357.5,48.5 --width-m 0.5 --tolerance ";
    for (const char* bad : {"-1", "inf", "nan", "0"}) {
        const auto r = test::run_command(overlay + bad + " 2>&1");
        EXPECT_EQ(r.exit_code, 2) << bad;
        EXPECT_NE(r.out.find("--tolerance"), std::string::npos) << r.out;
    }
    const std::string folds = test::foldcast_binary() + " folds " + photo + " -o " + out + " --min-length-px ";
    for (const char* bad : {"-1", "nan", "inf"}) {
        const auto r = test::run_command(folds + bad + " 2>&1");
        EXPECT_EQ(r.exit_code, 2) << bad;
        EXPECT_NE(r.out.find("--min-length-px"), std::string::npos) << r.out;
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "o.png"));
    // Supports on top of each other: one line naming them, exit 2.
    const auto same = test::run_command(test::foldcast_binary() + " overlay " + photo + " -o " + out +
                                        " --supports 200,50,200,50 2>&1");
    EXPECT_EQ(same.exit_code, 2);
    EXPECT_NE(same.out.find("supports"), std::string::npos) << same.out;
}
