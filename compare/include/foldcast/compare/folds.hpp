#pragma once
// Fold detection in photographs of hanging cloth: a cloth mask (given, or GrabCut seeded
// around and below the two supports), prints separated from shading by their chromaticity
// (shading scales linear RGB, a print changes its ratios), each print colour scaled to the
// cloth's brightness (a fold through a print stays visible) and its outlines filled in, a multi-scale
// Hessian ridge/valley filter with gamma-normalised responses (Lindeberg) on the shading,
// non-maximum suppression across the ridge with sub-pixel positions, hysteresis, and
// linking into polylines.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "foldcast/compare/image.hpp"

namespace foldcast::compare {

// The two supports (grippers, clips) in pixel coordinates, x right, y down.
struct SupportPixels {
    Eigen::Vector2d first{0, 0};
    Eigen::Vector2d second{0, 0};
    double distance_px() const { return (second - first).norm(); }
};

// Throws InputError (one line, naming "supports") unless both supports are finite, lie
// inside a width x height image and are at least 2 px apart.
void validate_supports(const SupportPixels& supports, int width, int height);

// +1 crest: a bright ridge of image luminance (a fold towards the light); -1 valley: a dark
// line (the shaded trough of a fold).
struct DetectedFold {
    int sign = 1;
    std::vector<Eigen::Vector2d> points_px;  // sub-pixel centre line, in order
    double mean_strength = 0.0;              // mean normalised ridge response along the line
    double length_px() const;
};

struct FoldDetectionOptions {
    std::vector<double> sigmas_px;  // empty: 5 scales, a factor sqrt(2) apart, from max(1.5, diagonal/600)
    double gamma = 0.75;            // scale normalisation t^gamma (Lindeberg's choice for ridges)
    double high_threshold = 0.0;    // 0: 4 x median response (of the relative shading) over the search region
    double low_ratio = 0.5;         // low threshold = low_ratio x high
    double min_length_px = 0.0;     // 0: max(10, 3 % of the image diagonal)
    bool exclude_prints = true;     // ignore printed motifs: pixels whose chromaticity is far from the cloth's
};
// Throws InputError naming the field unless every value is finite and in range
// (sigmas > 0, gamma in [0, 2], thresholds >= 0, low_ratio in (0, 1], min_length_px >= 0).
void validate(const FoldDetectionOptions& options);

struct FoldDetection {
    std::vector<DetectedFold> folds;
    Image mask;           // 1 channel, 1 = cloth
    Image search_region;  // 1 channel, 1 = where lines were looked for (mask minus border, prints)
    Image print_mask;     // 1 channel, 1 = printed motif (chromaticity far from the cloth's), dilated
    // 1 channel, 1 = where the shading cannot be read: around a change of colour (a print's
    // outline, one print colour against another) and on prints too small to normalise
    // (dilated).  Inside a print of one colour the shading is read (scaled to the cloth).
    Image print_outline;
    Image luma;  // 1 channel: the photo's luma, prints scaled to the cloth and their outlines filled in
    // 1 channel: what the ridge filter saw, the relative shading log(luma / m + 0.5), m the
    // cloth's median luma: a fold's response does not depend on the cloth's albedo.
    Image shading;
    std::vector<double> sigmas_px;
    // A line is seeded where the shading's response clears high_threshold and the luma's
    // clears high_floor (the photo's noise floor, in stored values); it grows through the low ones.
    double high_threshold = 0.0, low_threshold = 0.0;
    double high_floor = 0.0, low_floor = 0.0;
};

// Cloth mask by GrabCut: from 0.4 D beside the supports (D = support distance) down to the
// picture's bottom may be cloth, everything else is background; the cloth is surely where
// it first shows going down the centre line from the support line (below a sagging top
// edge the background shows through).  Largest component, holes filled.  Deterministic.
// Without supports the whole image counts as cloth.
Image estimate_cloth_mask(const Image& photo, const std::optional<SupportPixels>& supports);

// Reads a mask file: any pixel above half scale is cloth.  Throws InputError naming the file
// if its size differs from width x height or it holds no cloth pixel.
Image read_mask(const std::filesystem::path& path, int width, int height);

// Throws InputError unless the mask has the photo's size and at least one cloth pixel.
FoldDetection detect_folds(const Image& photo, const Image& mask, const FoldDetectionOptions& options = {});

// The photo with the mask outline (yellow), crests (orange, solid) and valleys (cyan).
Image draw_detected_folds(const Image& photo, const FoldDetection& detection);

}  // namespace foldcast::compare
