// foldcast overlay PHOTO -o OUT.png --supports ...: predicted fold lines (drape) drawn over a
// photo; --score compares them with the folds detected in the photo, --fit searches the
// inset and load constant for the best agreement.
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "commands.hpp"
#include "foldcast/compare/overlay.hpp"
#include "foldcast/core/atomic_file.hpp"
#include "foldcast/looks.hpp"

namespace foldcast::app {
namespace {

struct OverlayOptions {
    std::string photo, output, supports, corners, mask, look = "cotton_jersey";
    std::optional<double> width_m, height_m, scale_px_per_m;
    double inset_m = 0.05;
    std::optional<double> thickness_mm, young_mpa, poisson, gsm, load_constant;
    double tolerance = 0.02;
    bool json = false, score = false, fit = false;
};

std::string fixed(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

// Height of the cloth below the support line, measured on the mask (pixels).
double mask_height_px(const compare::Image& mask, const compare::SupportPixels& s) {
    const Eigen::Vector2d ex = (s.second - s.first).normalized(), down(-ex.y(), ex.x());
    const Eigen::Vector2d mid = 0.5 * (s.first + s.second);
    double lowest = 0.0;
    for (int y = 0; y < mask.height; ++y)
        for (int x = 0; x < mask.width; ++x)
            if (mask.at(x, y, 0) > 0.5f) lowest = std::max(lowest, (Eigen::Vector2d(x, y) - mid).dot(down));
    return lowest;
}

nlohmann::json score_json(const compare::FoldScore& s) {
    return {{"predicted_folds", s.predicted_folds}, {"detected_folds", s.detected_folds},
            {"chamfer_cm", s.chamfer_cm},           {"chamfer_truncated_at_cm", s.truncation_cm},
            {"precision", s.precision},             {"recall", s.recall},
            {"f1", s.f1},                           {"tolerance_px", s.tolerance_px},
            {"tolerance_cm", s.tolerance_cm}};
}

int run_overlay(const OverlayOptions& o) {
    check_writable(o.output);
    check_not_input(o.output, o.photo, "-o");
    const compare::Image photo = compare::read_image(o.photo);
    const compare::SupportPixels supports = compare::parse_supports(o.supports);
    compare::validate_supports(supports, photo.width, photo.height);
    if (o.width_m.has_value() == o.scale_px_per_m.has_value())
        throw InputError("give either --width-m and --height-m, or --scale-px-per-m (not both, not neither)");
    if (o.width_m && !o.height_m) throw InputError("--width-m needs --height-m");
    if (o.scale_px_per_m && !(*o.scale_px_per_m > 0))
        throw InputError("--scale-px-per-m " + std::to_string(*o.scale_px_per_m) + ": must be > 0");
    std::optional<std::array<Eigen::Vector2d, 4>> corners;
    if (!o.corners.empty()) {
        const auto v = compare::parse_numbers(o.corners, 8, "--corners");
        corners = std::array<Eigen::Vector2d, 4>{Eigen::Vector2d(v[0], v[1]), Eigen::Vector2d(v[2], v[3]),
                                                 Eigen::Vector2d(v[4], v[5]), Eigen::Vector2d(v[6], v[7])};
    }

    looks::Mechanics mech = looks::Library::load_default().get(o.look).mechanics;
    if (o.thickness_mm) mech.thickness_mm = *o.thickness_mm;
    if (o.young_mpa) mech.young_mpa = *o.young_mpa;
    if (o.poisson) mech.poisson = *o.poisson;
    if (o.gsm) mech.gsm = *o.gsm;
    if (o.load_constant) mech.load_constant = *o.load_constant;

    const bool need_mask = o.score || o.fit || (o.scale_px_per_m && !o.height_m);
    compare::Image mask;
    if (need_mask)
        mask = o.mask.empty() ? compare::estimate_cloth_mask(photo, supports)
                              : compare::read_mask(o.mask, photo.width, photo.height);

    // Physical size: given, or from the scale (span = support distance / scale).
    const double d_px = supports.distance_px();
    double width_m = 0.0, height_m = 0.0;
    if (o.width_m) {
        width_m = *o.width_m;
        height_m = *o.height_m;
    } else {
        width_m = d_px / *o.scale_px_per_m + 2.0 * o.inset_m;
        height_m = o.height_m ? *o.height_m : mask_height_px(mask, supports) / *o.scale_px_per_m;
    }
    drape::ClothParams params = drape::cloth_from_look(mech, width_m, height_m, o.inset_m);
    drape::validate(params);

    // In W/H mode the scale follows the span W - 2d; in scale mode the span is fixed by the
    // photo and a changed inset changes the width instead.
    const bool fixed_scale = o.scale_px_per_m.has_value();
    auto map_for = [&](const drape::ClothParams& p) {
        if (corners) return compare::homography_from_corners(*corners, p.support_span_m(), p.height_m);
        return compare::similarity_from_supports(supports, p.support_span_m());
    };

    std::optional<compare::FoldDetection> detection;
    double tolerance_px = o.tolerance * d_px;
    if (o.score || o.fit) detection = compare::detect_folds(photo, mask);

    std::optional<compare::FitResult> fit;
    if (o.fit) {
        fit = compare::fit_folds(params, map_for, *detection, tolerance_px, fixed_scale);
        params = fit->params;
    }

    const drape::FoldSolution solution = drape::solve_folds(params);
    const compare::ClothToImage map = map_for(params);
    const auto lines = compare::project_fold_lines(drape::fold_lines(params, solution), solution.folds, map);
    std::optional<compare::FoldScore> score;
    if (detection) score = compare::score_folds(lines, *detection, map.px_per_m, tolerance_px);

    std::vector<std::string> legend;
    if (solution.folds > 0)
        legend.push_back("n = " + std::to_string(solution.folds) + " folds   Q = " + fixed(solution.Q, 3) +
                         "   zmax = " + fixed(100 * solution.zmax_m, 1) + " cm");
    else
        legend.push_back("no folds predicted (" + solution.explanation + ")");
    legend.push_back(o.look + ": " + fixed(100 * params.width_m, 0) + " x " + fixed(100 * params.height_m, 0) +
                     " cm, inset " + fixed(100 * params.inset_m, 1) + " cm" + (o.fit ? " (fitted)" : ""));
    if (score)
        legend.push_back("detected " + std::to_string(score->detected_folds) + " lines: chamfer " +
                         fixed(score->chamfer_cm, 1) + " cm, P " + fixed(score->precision, 2) + " R " +
                         fixed(score->recall, 2) + " @ " + fixed(score->tolerance_cm, 1) + " cm");
    compare::write_image(o.output, compare::draw_overlay(photo, lines, supports, legend));

    if (o.json) {
        nlohmann::json jl = nlohmann::json::array();
        for (const auto& l : lines) {
            nlohmann::json pts = nlohmann::json::array();
            for (const auto& p : l.points_px) pts.push_back({std::round(p.x() * 100) / 100, std::round(p.y() * 100) / 100});
            jl.push_back({{"index", l.index}, {"sign", l.sign}, {"top_edge", l.top_edge}, {"points_px", pts}});
        }
        nlohmann::json j{{"photo", o.photo},
                         {"output", o.output},
                         {"mapping", corners ? "homography" : "similarity"},
                         {"px_per_m", map.px_per_m},
                         {"look", o.look},
                         {"params",
                          {{"width_m", params.width_m},
                           {"height_m", params.height_m},
                           {"inset_m", params.inset_m},
                           {"span_m", params.support_span_m()},
                           {"thickness_m", params.thickness_m},
                           {"young_pa", params.young_pa},
                           {"poisson", params.poisson},
                           {"weight_n_per_m2", params.weight_n_per_m2},
                           {"load_constant", params.load_constant}}},
                         {"folds", solution.folds},
                         {"Q", solution.Q},
                         {"zmax_m", solution.zmax_m},
                         {"amplitudes_m", solution.amplitudes_m},
                         {"explanation", solution.explanation},
                         {"lines", jl}};
        if (score) j["score"] = score_json(*score);
        if (fit) j["fit"] = {{"evaluated", fit->evaluated}, {"inset_m", fit->params.inset_m}, {"load_constant", fit->params.load_constant}};
        std::printf("%s\n", j.dump(1).c_str());
    } else {
        std::printf("%d folds predicted (Q %.3f, zmax %.1f cm) -> %s\n", solution.folds, solution.Q, 100 * solution.zmax_m,
                    o.output.c_str());
        if (score)
            std::printf("score: %d predicted, %d detected, chamfer %.2f cm, precision %.2f, recall %.2f, F1 %.2f (tolerance %.2f cm)\n",
                        score->predicted_folds, score->detected_folds, score->chamfer_cm, score->precision, score->recall,
                        score->f1, score->tolerance_cm);
        if (fit)
            std::printf("fit: inset %.3f m, load constant %.3f (%d parameter sets tried)\n", fit->params.inset_m,
                        fit->params.load_constant, fit->evaluated);
    }
    return 0;
}

}  // namespace

Command overlay_command(CLI::App& app) {
    auto o = std::make_shared<OverlayOptions>();
    CLI::App* sub = app.add_subcommand("overlay", "Draw the predicted fold lines over a photo of cloth hung from two supports");
    sub->add_option("photo", o->photo, "Photo (PNG, JPEG, ...)")->required();
    sub->add_option("-o,--output", o->output, "Output picture, same size as the photo")->required();
    sub->add_option("--supports", o->supports, "X1,Y1,X2,Y2: the two supports in pixels")->required();
    sub->add_option("--width-m", o->width_m, "Cloth width L (top edge) in metres; with --height-m");
    sub->add_option("--height-m", o->height_m, "Cloth height h in metres (with --scale-px-per-m: default measured on the cloth mask)");
    sub->add_option("--scale-px-per-m", o->scale_px_per_m, "Pixels per metre in the cloth plane (instead of --width-m)");
    sub->add_option("--inset-m", o->inset_m, "Support inset d: supports are L - 2d apart")->capture_default_str();
    sub->add_option("--corners", o->corners,
                    "X1,Y1,...,X4,Y4: support 1, support 2, hem below support 2, hem below support 1 (perspective fit)");
    sub->add_option("--look", o->look, "Fabric look (foldcast looks)")->capture_default_str();
    sub->add_option("--thickness-mm", o->thickness_mm, "Override the look's thickness");
    sub->add_option("--young-mpa", o->young_mpa, "Override the look's Young's modulus");
    sub->add_option("--poisson", o->poisson, "Override the look's Poisson's ratio");
    sub->add_option("--gsm", o->gsm, "Override the look's weight in g/m^2");
    sub->add_option("--load-constant", o->load_constant, "Override the look's load constant c");
    sub->add_option("--mask", o->mask, "Cloth mask for --score/--fit (default: GrabCut around the supports)");
    sub->add_option("--tolerance", o->tolerance, "Precision/recall tolerance as a share of the support distance")
        ->capture_default_str();
    sub->add_flag("--score", o->score, "Compare with the folds detected in the photo");
    sub->add_flag("--fit", o->fit, "Search the inset and load constant for the best score (implies --score)");
    sub->add_flag("--json", o->json, "Print parameters, lines, score and fit as one JSON object");
    return {sub, [o] { return run_overlay(*o); }};
}

}  // namespace foldcast::app
