// One photo -> geometry from the cloth mask, the model's fold lines, score and fit.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "foldcast/compare/photo_overlay.hpp"

namespace foldcast::compare {
namespace {

std::string fixed(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

void check_positive(const std::optional<double>& v, const char* name) {
    if (v && !(std::isfinite(*v) && *v > 0))
        throw InputError(std::string("overlay: ") + name + " = " + std::to_string(*v) +
                         "; it must be a finite number > 0");
}

// Why the model draws no fold, in the legend's few words; the same cause as drape's
// one-sentence explanation (printed beside it on the console).  drape reports a taut top
// edge (inset 0, no slack) as no_feasible_folds.
std::string no_folds_reason(const drape::FoldSolution& s, const drape::ClothParams& p) {
    if (s.regime == drape::FoldSolution::Regime::no_wrinkles) return "too stiff: S >= 1";
    if (p.inset_m == 0.0) return "no slack: inset 0, the top edge is taut";
    return "no n solves the model";
}

}  // namespace

ClothExtent measure_cloth(const Image& mask, const SupportPixels& s) {
    const double d = s.distance_px();
    const Eigen::Vector2d ex = (s.second - s.first) / d, down(-ex.y(), ex.x());
    const Eigen::Vector2d mid = 0.5 * (s.first + s.second);
    ClothExtent e;
    double lo = 0.0, hi = 0.0;
    bool any = false, band = false;
    for (int y = 0; y < mask.height; ++y)
        for (int x = 0; x < mask.width; ++x) {
            if (!(mask.at(x, y, 0) > 0.5f)) continue;
            any = true;
            const Eigen::Vector2d r = Eigen::Vector2d(x, y) - mid;
            const double depth = r.dot(down), along = r.dot(ex);
            e.height_px = std::max(e.height_px, depth);
            if (depth >= -0.1 * d && depth <= 0.25 * d) {
                lo = band ? std::min(lo, along) : along;
                hi = band ? std::max(hi, along) : along;
                band = true;
            }
        }
    if (!any)
        throw InputError("cloth mask: empty (no cloth pixel); give a mask with the cloth in white or other supports");
    if (!band || !(e.height_px > 0))
        throw InputError("cloth mask: no cloth just below the supports; the supports must hold the cloth's top edge");
    e.width_px = hi - lo + 1.0;
    return e;
}

void validate(const OverlayRequest& r, int photo_width, int photo_height) {
    validate_supports(r.supports, photo_width, photo_height);
    check_positive(r.scale_px_per_m, "scale_px_per_m");
    check_positive(r.width_m, "width_m");
    check_positive(r.height_m, "height_m");
    if (r.inset_m && !(std::isfinite(*r.inset_m) && *r.inset_m >= 0))
        throw InputError("overlay: inset_m = " + std::to_string(*r.inset_m) + "; it must be a finite number >= 0");
    if (r.scale_px_per_m && r.width_m && r.inset_m)
        throw InputError(
            "overlay: scale_px_per_m, width_m and inset_m together over-determine the support span; "
            "give at most two of them");
    if (!(std::isfinite(r.tolerance) && r.tolerance > 0 && r.tolerance <= 1))
        throw InputError("overlay: tolerance = " + std::to_string(r.tolerance) +
                         "; allowed: a share of the support distance in (0, 1]");
    if (r.mask && (r.mask->width != photo_width || r.mask->height != photo_height))
        throw InputError("overlay: the mask is " + std::to_string(r.mask->width) + "x" +
                         std::to_string(r.mask->height) + ", the photo " + std::to_string(photo_width) + "x" +
                         std::to_string(photo_height));
}

namespace {

// The cloth's size in metres and the photo's scale: from the request where it gives them,
// else read off the mask (each such reading added to `assumptions`).
struct PhotoGeometry {
    double width_m = 0.0, inset_m = 0.0, px_per_m = 0.0, height_m = 0.0;
};

PhotoGeometry photo_geometry(const OverlayRequest& r, const ClothExtent& extent, double d_px,
                             std::vector<std::string>& assumptions) {
    // The inset seen on the photo: how far the cloth reaches beyond the supports along their
    // line (a lower bound: a corner hanging down reaches less far than it would flat).
    const double inset_px = std::max(0.0, 0.5 * (extent.width_px - d_px));
    double width_m = 0.0, inset_m = 0.0, px_per_m = 0.0;
    if (r.scale_px_per_m) {
        px_per_m = *r.scale_px_per_m;
        const double span_m = d_px / px_per_m;
        if (r.width_m) {
            width_m = *r.width_m;
            inset_m = 0.5 * (width_m - span_m);
            if (!(inset_m >= 0))
                throw InputError("overlay: width_m = " + fixed(width_m, 3) + " is less than the support span " +
                                 fixed(span_m, 3) + " m (support distance / scale_px_per_m)");
        } else {
            inset_m = r.inset_m ? *r.inset_m : inset_px / px_per_m;
            width_m = span_m + 2.0 * inset_m;
            assumptions.push_back(r.inset_m ? "width = span + 2 inset" : "width and inset from the mask");
        }
    } else {
        width_m = r.width_m.value_or(kAssumedWidthM);
        if (!r.width_m) assumptions.push_back("width assumed");
        if (r.inset_m) {
            inset_m = *r.inset_m;
        } else {
            inset_m = width_m * inset_px / (d_px + 2.0 * inset_px);
            assumptions.push_back("inset from the mask");
        }
        if (!(width_m - 2.0 * inset_m > 0))
            throw InputError("overlay: inset_m = " + fixed(inset_m, 3) +
                             " leaves no support span of width_m = " + fixed(width_m, 3) + " (need inset < width / 2)");
        px_per_m = d_px / (width_m - 2.0 * inset_m);
    }
    double height_m = 0.0;
    if (r.height_m) {
        height_m = *r.height_m;
    } else {
        height_m = extent.height_px / px_per_m;
        assumptions.push_back("height from mask");
    }
    return {width_m, inset_m, px_per_m, height_m};
}

// The fit's legend lines.  A value the photo does not decide (its 5 % range is the whole box)
// is shown as "?" with the box, not as a precise-looking number; "*": the best lies on a bound.
void add_fit_legend(const FitResult& f, double px_per_m, std::vector<std::string>& legend) {
    auto value = [](const FittedValue& v, double unit, int digits, const std::string& name) {
        if (!v.constrained)
            return "? " + name + " [" + fixed(v.bound_min / unit, digits) + ", " + fixed(v.bound_max / unit, digits) +
                   "]";
        return fixed(v.best / unit, digits) + (v.on_bound ? "*" : "") + " " + name + " [" +
               fixed(v.low / unit, digits) + ", " + fixed(v.high / unit, digits) + "]";
    };
    legend.push_back("fit: E " + value(f.young_pa, 1e6, 2, "MPa") + ", inset " + value(f.inset_m, 0.01, 1, "cm"));
    if ((f.young_pa.on_bound && f.young_pa.constrained) || (f.inset_m.on_bound && f.inset_m.constrained))
        legend.push_back("* on a bound of the search");
    if (!f.young_pa.constrained || !f.inset_m.constrained)
        legend.push_back("? not decided: the whole search range scores within 5 %");
    // Why nothing matched, when the model's reach says so: that line replaces the plain
    // "only n fitted" (the legend has to fit beside the cloth).
    if (f.nothing_matched && !(f.reach && f.reach->outside))
        legend.push_back("no line on a detected fold: only n fitted");
    if (f.reach && f.reach->outside) {
        // The model cannot put the measured folds where the photo has them (in this box).
        const double cm = 100.0 / px_per_m;
        const auto& rc = *f.reach;
        const std::string n = std::to_string(rc.folds);
        if (rc.sets == 0)
            legend.push_back("model: no set in the box has n = " + n);
        else if (rc.measured_px < rc.lowest_min_px)
            legend.push_back("model: n = " + n + " folds lie >= " + fixed(rc.lowest_min_px * cm, 1) +
                             " cm down, photo " + fixed(rc.measured_px * cm, 1) + " cm");
        else
            legend.push_back("model: n = " + n + " folds lie <= " + fixed(rc.lowest_max_px * cm, 1) +
                             " cm down, photo " + fixed(rc.measured_px * cm, 1) + " cm");
    }
}

// Legend: predicted against measured first, the numbers a textile engineer compares;
// short lines, so that it fits beside the cloth (where layout_legend puts it).
void add_legend(OverlayResult& out, const OverlayRequest& r, const drape::ClothParams& params) {
    const auto& s = out.solution;
    out.legend.push_back(s.folds > 0 ? "predicted: n = " + std::to_string(s.folds) + ", Q = " + fixed(s.Q, 2) +
                                           " (zmax " + fixed(100 * s.zmax_m, 1) + " cm)"
                                     : "predicted: no folds (" + no_folds_reason(s, params) + ")");
    const CentreLine& c = *out.centre;
    out.legend.push_back("measured: n = " + std::to_string(c.folds) +
                         (c.Q ? ", Q = " + fixed(*c.Q, 2) : std::string(", Q n/a")) + " (centre line)");
    if (out.score)
        out.legend.push_back("P " + fixed(out.score->precision, 2) + "  R " + fixed(out.score->recall, 2) + "  F1 " +
                             fixed(out.score->f1, 2) + " (within " + fixed(out.score->tolerance_cm, 1) + " cm)");
    if (out.fit) add_fit_legend(*out.fit, out.map.px_per_m, out.legend);
    out.legend.push_back(r.look_name + ": " + fixed(100 * params.width_m, 0) + " x " + fixed(100 * params.height_m, 0) +
                         " cm, inset " + fixed(100 * params.inset_m, 1) + " cm");
    if (!out.assumptions.empty()) {
        std::string line;
        for (size_t i = 0; i < out.assumptions.size(); ++i) line += (i ? "; " : "") + out.assumptions[i];
        out.legend.push_back(line);
    }
}

}  // namespace

OverlayResult overlay_photo(const Image& photo, const OverlayRequest& r) {
    validate(r, photo.width, photo.height);
    OverlayResult out;
    const SupportPixels& supports = r.supports;
    out.mask = r.mask ? *r.mask : estimate_cloth_mask(photo, supports);
    out.extent = measure_cloth(out.mask, supports);
    const double d_px = supports.distance_px();
    const PhotoGeometry geometry = photo_geometry(r, out.extent, d_px, out.assumptions);
    const double width_m = geometry.width_m, inset_m = geometry.inset_m, px_per_m = geometry.px_per_m,
                 height_m = geometry.height_m;
    drape::ClothParams params = drape::cloth_from_look(r.mechanics, width_m, height_m, inset_m);
    drape::validate(params);

    auto map_for = [&](const drape::ClothParams& p) {
        if (r.corners) return homography_from_corners(*r.corners, p.support_span_m(), p.height_m);
        return similarity_from_supports(supports, p.support_span_m());
    };

    // The folds in the photo and on its centre line: always, for the legend's measured n, Q.
    out.detection = detect_folds(photo, out.mask);
    out.centre = measure_centre_line(*out.detection, supports);
    const double tolerance_px = r.tolerance * d_px;

    if (r.fit) {
        FitBounds bounds;
        bounds.inset_min_m = 0.0;
        // Supports at least half the flat width apart: closer, the cloth bunches into the
        // grippers, outside the model's sheet-with-a-sagging-top-edge regime.
        bounds.inset_max_m = kInsetFitShare * width_m;
        bounds.young_min_pa = params.young_pa / kYoungFitFactor;
        bounds.young_max_pa = params.young_pa * kYoungFitFactor;
        // The pixels stay: with a scale the span is fixed and the width follows the inset;
        // with a width the span (so the scale) follows it, and so does a height read off
        // the mask.
        auto geometry_for = [&](drape::ClothParams p) {
            if (r.scale_px_per_m) {
                p.width_m = d_px / px_per_m + 2.0 * p.inset_m;
            } else if (!r.height_m) {
                p.height_m = out.extent.height_px * p.support_span_m() / d_px;
            }
            return p;
        };
        out.fit = fit_folds(params, bounds, geometry_for, map_for, out.mask, *out.detection, *out.centre, tolerance_px);
        params = out.fit->params;
        for (auto& a : out.assumptions)
            if (a == "inset from the mask" || a == "width and inset from the mask")
                a = r.scale_px_per_m ? "inset fitted, width = span + 2 inset" : "inset fitted";
        if (!r.height_m)
            for (auto& a : out.assumptions)
                if (a == "height from mask") a = "height from mask (fitted scale)";
    }
    out.params = params;
    out.solution = drape::solve_folds(params);
    out.map = map_for(params);
    out.lines = clip_to_cloth(project_fold_lines(drape::fold_lines(params, out.solution), out.solution.folds, out.map),
                              out.mask);
    if (r.score || r.fit) {
        out.score = score_folds(out.lines, *out.detection, *out.centre, out.map.px_per_m, tolerance_px);
        out.score->predicted_folds = out.solution.folds;
        out.score->count_error = out.solution.folds - out.centre->folds;
        out.score->agreement = agreement(out.score->f1, out.score->count_error);
    }

    add_legend(out, r, params);
    out.legend_layout = layout_legend(out.legend, photo.width, photo.height, out.mask, out.lines, supports);
    out.picture = draw_overlay(photo, out.lines, supports, out.legend, out.legend_layout);
    return out;
}

}  // namespace foldcast::compare
