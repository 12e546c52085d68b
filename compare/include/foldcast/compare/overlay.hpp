#pragma once
// Predicted fold lines over a photo: the cloth plane of drape's frame (origin midway between
// the supports, x right, y up, metres) mapped to pixels by a similarity fixed by the two
// supports, or by a homography fixed by four points; scoring against detected folds and a
// search of the model's free parameters for the best score.
#include <Eigen/Core>
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "foldcast/compare/folds.hpp"
#include "foldcast/drape.hpp"

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
    int index = 0;       // drape's i: 0 lowest; index == n is the top edge
    int sign = 1;        // +1 towards the viewer (crest), -1 away (valley)
    bool top_edge = false;
    std::vector<Eigen::Vector2d> points_px;
};
std::vector<PredictedLine> project_fold_lines(const std::vector<drape::FoldLine>& lines, int folds,
                                              const ClothToImage& map);

// The photo with positive folds solid black, negative folds dashed white (each with a thin
// halo of the other colour so both read on any cloth), supports ringed, and a legend box
// with `legend` lines in the corner that hides the fewest lines.  Same size as the photo.
Image draw_overlay(const Image& photo, const std::vector<PredictedLine>& lines, const SupportPixels& supports,
                   const std::vector<std::string>& legend);

struct FoldScore {
    int predicted_folds = 0;  // n (the top edge is not a fold)
    int detected_folds = 0;
    double chamfer_cm = 0.0;  // symmetric, truncated at `truncation_cm`
    double truncation_cm = 0.0;
    double precision = 0.0;   // share of detected line length within tolerance of a prediction
    double recall = 0.0;      // share of predicted line length (inside the region) within tolerance
    double f1 = 0.0;
    double tolerance_px = 0.0, tolerance_cm = 0.0;
};

// Compares predicted lines (clipped to the detection's search region) with the detected
// ones.  tolerance_px: distance for precision/recall; chamfer distances are truncated at 5x it.
FoldScore score_folds(const std::vector<PredictedLine>& predicted, const FoldDetection& detection, double px_per_m,
                      double tolerance_px);

struct FitResult {
    drape::ClothParams params;
    drape::FoldSolution solution;
    FoldScore score;
    int evaluated = 0;
};

// Grid search over the support inset (10 values from 0 to 0.4 x width, or with keep_span
// 0 to 0.4 x span with the width growing as span + 2 inset) and the load constant
// (x 2^-3 .. x 2^3 of `start`, 9 values) for the highest F1 (ties: lower chamfer distance).
// `map_for` gives the photo mapping of a parameter set.  Sets that the model rejects are
// skipped; sets without folds are scored too (recall 0).
FitResult fit_folds(const drape::ClothParams& start, const std::function<ClothToImage(const drape::ClothParams&)>& map_for,
                    const FoldDetection& detection, double tolerance_px, bool keep_span = false);

}  // namespace foldcast::compare
