// foldcast folds PHOTO -o OUT.png: detect fold lines (crests and valleys) in a photo of
// hanging cloth and draw them; --json lists the polylines.
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "foldcast/compare/folds.hpp"
#include "foldcast/core/atomic_file.hpp"
#include "validators.hpp"

namespace foldcast::app {
namespace {

struct FoldsOptions {
    std::string photo, output, mask;
    std::vector<double> supports;
    double min_length_px = 0.0;
    bool keep_prints = false;
    bool json = false;
};

double round2(double v) { return std::round(v * 100.0) / 100.0; }

int run_folds(const FoldsOptions& o) {
    check_writable(o.output);
    check_not_input(o.output, o.photo, "-o");
    const compare::Image photo = compare::read_image(o.photo);
    std::optional<compare::SupportPixels> supports;
    if (!o.supports.empty()) {
        supports = compare::SupportPixels{Eigen::Vector2d(o.supports[0], o.supports[1]),
                                          Eigen::Vector2d(o.supports[2], o.supports[3])};
        compare::validate_supports(*supports, photo.width, photo.height);
    }
    const compare::Image mask = o.mask.empty() ? compare::estimate_cloth_mask(photo, supports)
                                               : compare::read_mask(o.mask, photo.width, photo.height);
    compare::FoldDetectionOptions options;
    options.min_length_px = o.min_length_px;
    options.exclude_prints = !o.keep_prints;
    const compare::FoldDetection detection = compare::detect_folds(photo, mask, options);
    compare::write_image(o.output, compare::draw_detected_folds(photo, detection));

    int crests = 0;
    for (const auto& f : detection.folds) crests += f.sign > 0;
    if (o.json) {
        nlohmann::json folds = nlohmann::json::array();
        for (const auto& f : detection.folds) {
            nlohmann::json points = nlohmann::json::array();
            for (const auto& p : f.points_px) points.push_back({round2(p.x()), round2(p.y())});
            folds.push_back({{"sign", f.sign > 0 ? "crest" : "valley"},
                             {"length_px", round2(f.length_px())},
                             {"mean_strength", f.mean_strength},
                             {"points_px", points}});
        }
        nlohmann::json j{{"photo", o.photo},
                         {"output", o.output},
                         {"width", photo.width},
                         {"height", photo.height},
                         {"mask", o.mask.empty() ? (supports ? "grabcut" : "whole image") : o.mask},
                         {"sigmas_px", detection.sigmas_px},
                         // On the relative shading's response; the floors on the luma's.
                         {"high_threshold", detection.high_threshold},
                         {"low_threshold", detection.low_threshold},
                         {"high_floor", detection.high_floor},
                         {"low_floor", detection.low_floor},
                         {"count", detection.folds.size()},
                         {"crests", crests},
                         {"valleys", static_cast<int>(detection.folds.size()) - crests},
                         {"folds", folds}};
        std::printf("%s\n", j.dump(1).c_str());
    } else {
        std::printf("%zu fold lines (%d crests, %d valleys) -> %s\n", detection.folds.size(), crests,
                    static_cast<int>(detection.folds.size()) - crests, o.output.c_str());
    }
    return 0;
}

}  // namespace

Command folds_command(CLI::App& app) {
    auto o = std::make_shared<FoldsOptions>();
    CLI::App* sub =
        app.add_subcommand("folds", "Detect fold lines (bright crests, dark valleys) in a photo of hanging cloth");
    sub->add_option("photo", o->photo, "Photo (PNG, JPEG, ...)")->required();
    sub->add_option("-o,--output", o->output, "Picture with the detected lines drawn (PNG)")->required();
    sub->add_option("--mask", o->mask, "Cloth mask image (white = cloth), same size as the photo");
    const double inf = std::numeric_limits<double>::infinity();
    sub->add_option("--supports", o->supports, "X1,Y1,X2,Y2: the supports in pixels; seeds the GrabCut cloth mask")
        ->delimiter(',')
        ->expected(4)
        ->check(finite_in(-inf, inf));
    sub->add_option("--min-length-px", o->min_length_px,
                    "Drop lines shorter than this (default 0: max(10, 3 % of the diagonal))")
        ->check(finite_in(0, inf));
    sub->add_flag("--keep-prints", o->keep_prints,
                  "Also look for lines on printed motifs (off: prints, told from shading by their chromaticity, are "
                  "filled in and masked out)");
    sub->add_flag("--json", o->json, "Print the polylines as one JSON object");
    return {sub, [o] { return run_folds(*o); }};
}

}  // namespace foldcast::app
