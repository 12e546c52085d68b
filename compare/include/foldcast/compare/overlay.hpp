#pragma once
// Predicted fold lines over a photo: the cloth plane of drape's frame (origin midway between
// the supports, x right, y up, metres) mapped to pixels by a similarity fixed by the two
// supports, or by a homography fixed by four points; clipping to the cloth, drawing,
// scoring against detected folds and the centre-line measurement, and a search of the
// model's physical parameters for the best agreement.  foldcast/compare/photo_overlay.hpp
// chains these for one photo.
#include <Eigen/Core>
#include <array>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "foldcast/compare/folds.hpp"
#include "foldcast/drape/drape.hpp"

namespace foldcast::compare {

// Cloth plane (x_m, y_m) -> pixel, as a 3x3 homography (a similarity is a special case).
struct ClothToImage {
    Eigen::Matrix3d h = Eigen::Matrix3d::Identity();
    double px_per_m = 1.0;  // scale along the support line, for converting distances to cm
    Eigen::Vector2d operator()(double x_m, double y_m) const;
};

// Similarity: support 1 is (-span/2, 0), support 2 is (+span/2, 0); y up in the cloth is
// up in the picture.
ClothToImage similarity_from_supports(const SupportPixels& supports, double span_m);
// Homography from four pixels, in this order: support 1, support 2, the hem below support
// 2, the hem below support 1, i.e. the cloth points (-l/2, 0), (l/2, 0), (l/2, -h), (-l/2, -h).
// Throws InputError if the four points are degenerate.
ClothToImage homography_from_corners(const std::array<Eigen::Vector2d, 4>& corners_px, double span_m, double height_m);

struct PredictedLine {
    int index = 0;  // drape's i: 0 lowest; index == n is the top edge
    int sign = 1;   // +1 towards the viewer (crest), -1 away (valley)
    bool top_edge = false;
    std::vector<Eigen::Vector2d> points_px;
};
std::vector<PredictedLine> project_fold_lines(const std::vector<drape::FoldLine>& lines, int folds,
                                              const ClothToImage& map);

// The pieces of the fold lines (top edge dropped: it is the cloth's outline, not a fold)
// that lie on the cloth: each line is cut where it leaves the mask (1 channel, > 0.5 =
// cloth); a line may become several pieces with the same index.  Pieces shorter than
// 2 px are dropped.
std::vector<PredictedLine> clip_to_cloth(const std::vector<PredictedLine>& lines, const Image& mask);

// The photo with positive folds solid black, negative folds dashed white (each with a thin
// halo of the other colour so both read on any cloth), line widths proportional to the
// image's diagonal, supports ringed, and a legend box with `legend` lines where `layout`
// says (foldcast/compare/legend_layout.hpp): the photo's size, or larger by the layout's
// band.  Without a layout, layout_legend's for the cloth `mask` (may be empty).
struct LegendLayout;
Image draw_overlay(const Image& photo, const std::vector<PredictedLine>& lines, const SupportPixels& supports,
                   const std::vector<std::string>& legend, const LegendLayout& layout);
Image draw_overlay(const Image& photo, const std::vector<PredictedLine>& lines, const SupportPixels& supports,
                   const std::vector<std::string>& legend, const Image& mask = {});

// The folds seen along the centre fibre (the vertical through the supports' midpoint, at
// right angles to the support line): the shading profile averaged over a band +/- 2 % of
// the support distance wide, its crests (bright) and valleys (dark) found with the
// detector's scales and threshold, in 1-D.  Depths are pixels below the support line.
struct CentreLine {
    double top_edge_depth_px = 0.0;  // first cloth pixel on the fibre: the top edge's sag a_n
    double hem_depth_px = 0.0;       // last cloth pixel on the fibre
    std::vector<double> depths_px;   // each crest/valley, top to bottom
    std::vector<int> signs;          // +1 crest (bright), -1 valley (dark)
    int folds = 0;                   // measured n: crests and valleys on the fibre
    // Measured Q, as drape's a_{i-1} = Q a_i: with two or more folds (deepest / shallowest
    // fold depth)^(1/(n-1)); with one, its depth over the top edge's sag; unset without
    // folds, or with one fold and a top edge that does not sag (< 2 px).
    std::optional<double> Q;
};
CentreLine measure_centre_line(const FoldDetection& detection, const SupportPixels& supports);

struct FoldScore {
    int predicted_folds = 0;  // n of the prediction (the top edge is not a fold)
    int detected_lines = 0;   // lines the detector found
    int measured_folds = 0;   // n on the centre line (CentreLine::folds)
    int count_error = 0;      // predicted_folds - measured_folds
    double precision = 0.0;   // share of predicted line length on the cloth within tolerance of a detected line
    double recall = 0.0;      // share of detected line length within tolerance of a predicted line
    double f1 = 0.0;
    // What the fit maximises, in [0, 1]: the mean of F1 (where the lines are) and
    // 1 / (1 + |count_error|) (how many there are).  More lines than the photo shows lower
    // the precision and the count term, so covering the cloth does not pay; the count term
    // still ranks parameter sets whose lines all miss (F1 = 0).
    double agreement = 0.0;
    double chamfer_cm = 0.0;  // symmetric, truncated at `truncation_cm`
    double truncation_cm = 0.0;
    double tolerance_px = 0.0, tolerance_cm = 0.0;
};

// FoldScore::agreement from its parts.
double agreement(double f1, int count_error);

// Compares predicted lines (clipped to the detection's search region) with the detected
// ones.  tolerance_px: distance for precision/recall; chamfer distances are truncated at 5x
// it.  Throws InputError unless tolerance_px and px_per_m are finite and > 0.
FoldScore score_folds(const std::vector<PredictedLine>& predicted, const FoldDetection& detection,
                      const CentreLine& centre, double px_per_m, double tolerance_px);

// The box the fit searches.  Inset d: [inset_min_m, inset_max_m].  Stiffness: only the
// product c E enters the model (sigma_cr = c E t^2 / (l^2 (1 - nu^2))), so E is searched at
// the given thickness, weight and load constant, over [young_min_pa, young_max_pa].
struct FitBounds {
    double inset_min_m = 0.0, inset_max_m = 0.0;
    double young_min_pa = 0.0, young_max_pa = 0.0;
    int inset_steps = 12;  // evenly spaced, ends included
    int young_steps = 13;  // log-spaced, ends included
};

// A fitted value with the range of the parameter sets whose agreement is within 5 % of the
// best one, and whether the best lies on an end of the search box.  When that range spans
// the whole box (and the box is not a single value) the photo does not decide the value:
// `constrained` is false, and `best` is only the tie-break's pick (the set nearest the start).
struct FittedValue {
    double best = 0.0, low = 0.0, high = 0.0;
    double bound_min = 0.0, bound_max = 0.0;
    bool on_bound = false;
    bool constrained = true;
};

// Where the model can put the folds the photo shows: over the sets of the search box whose
// fold count equals the measured one, the depth (px below the support line, along the
// centre fibre) of their lowest fold line, beside the measured depth of the lowest fold.
// When the measured depth lies outside [lowest_min_px, lowest_max_px] (by more than the
// score's tolerance), no set with the right count draws its folds where the photo has
// them: the miss is the model's reach within the box, not the score's or the fit's.
struct ModelReach {
    int folds = 0;              // the measured count the sets were picked by
    int sets = 0;               // how many sets of the box the model solves with that count
    double lowest_min_px = 0.0, lowest_max_px = 0.0;
    double measured_px = 0.0;   // CentreLine::depths_px.back()
    bool outside = false;       // measured farther than the tolerance from [min, max], or no set has the count
};

struct FitResult {
    drape::ClothParams params;
    drape::FoldSolution solution;
    FoldScore score;
    FittedValue inset_m, young_pa;
    int evaluated = 0;
    bool nothing_matched = false;  // no set put any line on a detected fold (F1 = 0): only the count was fitted
    std::optional<ModelReach> reach;  // set when the centre line measured at least one fold
};

// Grid search of the box for the highest agreement.  Ties: the lower chamfer distance in
// pixels (in centimetres it would favour the sets whose scale makes a pixel small), then
// the set nearest the start (inset on its share of the box, E on the log of its range):
// the photo does not tell them apart, the physical default is the honest pick.
// `geometry_for` completes a parameter set for its inset (the photo fixes pixels, not metres:
// a new inset may change the width, or the scale and with it the height read off the mask);
// empty: width and height stay.  `map_for` gives the photo mapping of a parameter set;
// `mask` clips the lines to the cloth.  Sets that the model rejects are skipped.  Throws
// InputError if the bounds are not finite, ordered and positive where needed, or no set in
// the box can be solved.
using GeometryFn = std::function<drape::ClothParams(const drape::ClothParams&)>;
FitResult fit_folds(const drape::ClothParams& start, const FitBounds& bounds, const GeometryFn& geometry_for,
                    const std::function<ClothToImage(const drape::ClothParams&)>& map_for, const Image& mask,
                    const FoldDetection& detection, const CentreLine& centre, double tolerance_px);

}  // namespace foldcast::compare
