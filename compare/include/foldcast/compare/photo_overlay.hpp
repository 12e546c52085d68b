#pragma once
// One photo of cloth hung from two supports -> the cloth's geometry from its mask, the
// model's fold lines on it, their score against the folds in the photo and, on request, a
// fit of the physical parameters.  What `foldcast overlay` does; the app only maps its
// flags onto OverlayRequest.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "foldcast/compare/legend_layout.hpp"
#include "foldcast/compare/overlay.hpp"
#include "foldcast/looks/looks.hpp"

namespace foldcast::compare {

// Extent of the cloth mask relative to the support line (D = support distance).
struct ClothExtent {
    double width_px = 0.0;   // along the support line, over the band 0.1 D above to 0.25 D below it
    double height_px = 0.0;  // lowest cloth pixel below the support line
};
// Throws InputError if the mask is empty or has no cloth in that band.
ClothExtent measure_cloth(const Image& mask, const SupportPixels& supports);

// Width assumed when neither a width nor a scale is given: an adult T-shirt's (the fit's
// stiffness absorbs most of a wrong guess, see docs/compare.md).
constexpr double kAssumedWidthM = 0.5;
// Plausible range of E relative to the look's, for the fit: bending moduli of fabrics of one
// kind measured by KES-FB2 or cantilever tests spread over about a decade each way.
constexpr double kYoungFitFactor = 10.0;
// The fit searches the inset from 0 to this share of the flat width (span >= width / 2).
constexpr double kInsetFitShare = 0.25;

struct OverlayRequest {
    SupportPixels supports;
    std::optional<std::array<Eigen::Vector2d, 4>> corners;  // homography instead of the similarity
    std::string look_name;
    looks::Mechanics mechanics;
    // Physical size, each optional: a scale (px per metre in the cloth plane), the width L,
    // the height h, the inset d.  What is missing comes from the mask (see docs/compare.md).
    std::optional<double> scale_px_per_m, width_m, height_m, inset_m;
    std::optional<Image> mask;  // else GrabCut around the supports
    double tolerance = 0.02;    // precision/recall distance as a share of the support distance
    bool score = false;
    bool fit = false;
};

// Throws InputError naming the field unless supports, sizes, scale and tolerance are finite
// and in range (tolerance in (0, 1]).
void validate(const OverlayRequest& request, int photo_width, int photo_height);

struct OverlayResult {
    drape::ClothParams params;
    drape::FoldSolution solution;
    ClothToImage map;
    std::vector<PredictedLine> lines;  // clipped to the cloth, no top edge: what is drawn
    Image mask;
    ClothExtent extent;
    std::vector<std::string> assumptions;  // sizes taken from the mask or assumed, in words
    std::optional<FoldDetection> detection;
    std::optional<CentreLine> centre;
    std::optional<FoldScore> score;
    std::optional<FitResult> fit;
    std::vector<std::string> legend;
    LegendLayout legend_layout;  // where the legend box went, in the picture
    Image picture;               // the photo with the lines and the legend (and the legend's band, if any)
};

OverlayResult overlay_photo(const Image& photo, const OverlayRequest& request);

}  // namespace foldcast::compare
