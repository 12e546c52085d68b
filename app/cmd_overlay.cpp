// foldcast overlay PHOTO -o OUT.png --supports ...: predicted fold lines (drape) drawn over a
// photo of cloth hung from two supports; --score compares them with the folds detected in
// the photo, --fit searches the inset and stiffness for the best agreement.  The analysis
// is compare::overlay_photo; this file maps flags onto its request and prints the result.
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "foldcast/compare/photo_overlay.hpp"
#include "foldcast/core/atomic_file.hpp"
#include "foldcast/looks/looks.hpp"
#include "validators.hpp"

namespace foldcast::app {
namespace {

struct OverlayOptions {
    std::string photo, output, mask, look = "cotton_jersey";
    std::vector<double> supports, corners;
    std::optional<double> width_m, height_m, scale_px_per_m, inset_m;
    std::optional<double> thickness_mm, young_mpa, poisson, gsm, load_constant;
    double tolerance = 0.02;
    bool json = false, score = false, fit = false;
};

nlohmann::json optional_number(const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

nlohmann::json fitted_json(const compare::FittedValue& v) {
    return {{"best", v.best},
            {"low", v.low},
            {"high", v.high},
            {"search_min", v.bound_min},
            {"search_max", v.bound_max},
            {"on_bound", v.on_bound},
            {"constrained", v.constrained}};
}

int run_overlay(const OverlayOptions& o) {
    check_writable(o.output);
    check_not_input(o.output, o.photo, "-o");
    const compare::Image photo = compare::read_image(o.photo);
    compare::OverlayRequest request;
    request.supports = {Eigen::Vector2d(o.supports[0], o.supports[1]), Eigen::Vector2d(o.supports[2], o.supports[3])};
    if (!o.corners.empty())
        request.corners = std::array<Eigen::Vector2d, 4>{
            Eigen::Vector2d(o.corners[0], o.corners[1]), Eigen::Vector2d(o.corners[2], o.corners[3]),
            Eigen::Vector2d(o.corners[4], o.corners[5]), Eigen::Vector2d(o.corners[6], o.corners[7])};
    request.look_name = o.look;
    request.mechanics = looks::Library::load_default().find(o.look).mechanics;
    looks::Mechanics& mech = request.mechanics;
    if (o.thickness_mm) mech.thickness_mm = *o.thickness_mm;
    if (o.young_mpa) mech.young_mpa = *o.young_mpa;
    if (o.poisson) mech.poisson = *o.poisson;
    if (o.gsm) mech.gsm = *o.gsm;
    if (o.load_constant) mech.load_constant = *o.load_constant;
    request.scale_px_per_m = o.scale_px_per_m;
    request.width_m = o.width_m;
    request.height_m = o.height_m;
    request.inset_m = o.inset_m;
    if (!o.mask.empty()) request.mask = compare::read_mask(o.mask, photo.width, photo.height);
    request.tolerance = o.tolerance;
    request.score = o.score;
    request.fit = o.fit;

    const compare::OverlayResult result = compare::overlay_photo(photo, request);
    compare::write_image(o.output, result.picture);

    const auto& s = result.solution;
    const auto& c = *result.centre;
    if (o.json) {
        nlohmann::json jl = nlohmann::json::array();
        for (const auto& l : result.lines) {
            nlohmann::json pts = nlohmann::json::array();
            for (const auto& p : l.points_px)
                pts.push_back({std::round(p.x() * 100) / 100, std::round(p.y() * 100) / 100});
            jl.push_back({{"index", l.index}, {"sign", l.sign}, {"points_px", pts}});
        }
        const auto& p = result.params;
        nlohmann::json j{{"photo", o.photo},
                         {"output", o.output},
                         {"mapping", request.corners ? "homography" : "similarity"},
                         {"px_per_m", result.map.px_per_m},
                         {"look", o.look},
                         {"assumptions", result.assumptions},
                         {"mask_extent_px", {{"width", result.extent.width_px}, {"height", result.extent.height_px}}},
                         {"params",
                          {{"width_m", p.width_m},
                           {"height_m", p.height_m},
                           {"inset_m", p.inset_m},
                           {"span_m", p.support_span_m()},
                           {"thickness_m", p.thickness_m},
                           {"young_pa", p.young_pa},
                           {"poisson", p.poisson},
                           {"weight_n_per_m2", p.weight_n_per_m2},
                           {"load_constant", p.load_constant}}},
                         {"predicted",
                          {{"folds", s.folds},
                           {"Q", s.Q},
                           {"zmax_m", s.zmax_m},
                           {"amplitudes_m", s.amplitudes_m},
                           {"explanation", s.explanation}}},
                         {"measured",
                          {{"folds", c.folds},
                           {"Q", optional_number(c.Q)},
                           {"top_edge_depth_px", c.top_edge_depth_px},
                           {"hem_depth_px", c.hem_depth_px},
                           {"depths_px", c.depths_px},
                           {"signs", c.signs}}},
                         {"detected_lines", result.detection->folds.size()},
                         {"picture_px", {{"width", result.picture.width}, {"height", result.picture.height}}},
                         {"legend",
                          {{"lines", result.legend},
                           {"place", compare::to_string(result.legend_layout.place)},
                           {"box_px",
                            {{"x", result.legend_layout.x},
                             {"y", result.legend_layout.y},
                             {"width", result.legend_layout.width},
                             {"height", result.legend_layout.height}}},
                           {"font_scale", result.legend_layout.font_scale}}},
                         {"lines", jl}};
        if (result.score) {
            const auto& sc = *result.score;
            j["score"] = {{"predicted_folds", sc.predicted_folds},
                          {"measured_folds", sc.measured_folds},
                          {"count_error", sc.count_error},
                          {"detected_lines", sc.detected_lines},
                          {"precision", sc.precision},
                          {"recall", sc.recall},
                          {"f1", sc.f1},
                          {"agreement", sc.agreement},
                          {"chamfer_cm", sc.chamfer_cm},
                          {"chamfer_truncated_at_cm", sc.truncation_cm},
                          {"tolerance_px", sc.tolerance_px},
                          {"tolerance_cm", sc.tolerance_cm}};
        }
        if (result.fit) {
            j["fit"] = {{"evaluated", result.fit->evaluated},
                        {"inset_m", fitted_json(result.fit->inset_m)},
                        {"young_pa", fitted_json(result.fit->young_pa)},
                        {"nothing_matched", result.fit->nothing_matched},
                        {"uncertainty", "range of the sets whose agreement is within 5 % of the best"}};
            if (const auto& r = result.fit->reach)
                j["fit"]["reach"] = {{"folds", r->folds},
                                     {"sets", r->sets},
                                     {"lowest_fold_min_px", r->lowest_min_px},
                                     {"lowest_fold_max_px", r->lowest_max_px},
                                     {"measured_lowest_fold_px", r->measured_px},
                                     {"outside", r->outside}};
        }
        std::printf("%s\n", j.dump(1).c_str());
    } else {
        for (const auto& line : result.legend) std::printf("%s\n", line.c_str());
        if (s.folds == 0) std::printf("why no folds: %s\n", s.explanation.c_str());
        std::printf("-> %s\n", o.output.c_str());
    }
    return 0;
}

}  // namespace

Command overlay_command(CLI::App& app) {
    auto o = std::make_shared<OverlayOptions>();
    CLI::App* sub =
        app.add_subcommand("overlay", "Draw the predicted fold lines over a photo of cloth hung from two supports");
    const double inf = std::numeric_limits<double>::infinity();
    sub->add_option("photo", o->photo, "Photo (PNG, JPEG, ...)")->required();
    sub->add_option("-o,--output", o->output,
                    "Output picture: the photo's size, or larger by a band holding the legend when no place on "
                    "the photo is clear of the cloth")
        ->required();
    sub->add_option("--supports", o->supports, "X1,Y1,X2,Y2: the two supports in pixels")
        ->required()
        ->delimiter(',')
        ->expected(4)
        ->check(finite_in(-inf, inf));
    sub->add_option("--scale-px-per-m", o->scale_px_per_m, "Pixels per metre in the cloth plane")
        ->check(finite_in(1e-9, inf, "a finite number > 0"));
    sub->add_option("--width-m", o->width_m,
                    "Cloth width L (top edge) in metres (default: from the scale and the mask, "
                    "else 0.5 m assumed)")
        ->check(finite_in(1e-9, inf, "a finite number > 0"));
    sub->add_option("--height-m", o->height_m, "Cloth height h in metres (default: measured on the cloth mask)")
        ->check(finite_in(1e-9, inf, "a finite number > 0"));
    sub->add_option("--inset-m", o->inset_m,
                    "Support inset d: supports are L - 2d apart (default: measured on the mask)")
        ->check(finite_in(0, inf));
    sub->add_option("--corners", o->corners,
                    "X1,Y1,...,X4,Y4: support 1, support 2, hem below support 2, hem below support 1 (perspective fit)")
        ->delimiter(',')
        ->expected(8)
        ->check(finite_in(-inf, inf));
    sub->add_option("--look", o->look, "Fabric look: a name (foldcast looks) or a look .toml file")
        ->capture_default_str();
    sub->add_option("--thickness-mm", o->thickness_mm, "Override the look's thickness")
        ->check(finite_in(1e-9, inf, "a finite number > 0"));
    sub->add_option("--young-mpa", o->young_mpa, "Override the look's Young's modulus")
        ->check(finite_in(1e-12, inf, "a finite number > 0"));
    sub->add_option("--poisson", o->poisson, "Override the look's Poisson's ratio")
        ->check(finite_in(0, 0.499999, "a number in [0, 0.5)"));
    sub->add_option("--gsm", o->gsm, "Override the look's weight in g/m^2")
        ->check(finite_in(1e-9, inf, "a finite number > 0"));
    sub->add_option("--load-constant", o->load_constant, "Override the look's load constant c")
        ->check(finite_in(1e-9, inf, "a finite number > 0"));
    sub->add_option("--mask", o->mask,
                    "Cloth mask, white = cloth, the photo's size (default: GrabCut around the supports)");
    sub->add_option("--tolerance", o->tolerance, "Precision/recall distance as a share of the support distance")
        ->check(finite_in(1e-9, 1.0, "a share of the support distance in (0, 1]"))
        ->capture_default_str();
    sub->add_flag("--score", o->score, "Print and draw the agreement with the folds detected in the photo");
    sub->add_flag("--fit", o->fit, "Search the inset and Young's modulus for the best agreement (implies --score)");
    sub->add_flag("--json", o->json, "Print parameters, measured and predicted folds, lines, score and fit as JSON");
    return {sub, [o] { return run_overlay(*o); }};
}

}  // namespace foldcast::app
