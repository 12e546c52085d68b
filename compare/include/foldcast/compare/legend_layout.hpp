#pragma once
// Where the overlay's legend goes and how large its text is.  A legend over the cloth hides
// the folds it describes, so the box is put only where it covers no cloth, no drawn line and
// no support; when the photo has no such place the picture grows by a band that holds it.
#include <string>
#include <vector>

#include "foldcast/compare/overlay.hpp"

namespace foldcast::compare {

// Smallest legend text: OpenCV's Hershey simplex at this scale has capitals about 8 px high,
// the least that reads on screen without zooming.
constexpr double kLegendMinFontScale = 0.35;

struct LegendLayout {
    enum class Place { photo, band_right, band_below };
    Place place = Place::photo;
    int x = 0, y = 0, width = 0, height = 0;    // the box, in the picture's pixels
    int picture_width = 0, picture_height = 0;  // the photo's size, or larger by the band
    double font_scale = 0.0;
};

// "photo", "band right", "band below".
const char* to_string(LegendLayout::Place place);

// The text starts at a size proportional to the photo's diagonal (at least the minimum) and
// may shrink to half that (never below the minimum) to find a clear place on the photo; of
// the clear places the one nearest a corner of the photo is taken.  Clear means: a gap of
// the box's padding away from the cloth (`mask`, > 0.5; may be empty), the drawn `lines`
// and the support rings, and inside the photo.  With none, the box goes at the starting
// size into a white band added on the right or below, whichever makes the smaller picture.
LegendLayout layout_legend(const std::vector<std::string>& legend, int photo_width, int photo_height, const Image& mask,
                           const std::vector<PredictedLine>& lines, const SupportPixels& supports);

}  // namespace foldcast::compare
