#pragma once
// Sizes of what the overlay draws, shared by the legend's layout (which must keep clear of
// the lines and rings) and the drawing (private to compare).
#include <string>
#include <vector>

namespace foldcast::compare::detail {

// Line widths and the support ring, from the photo's size.
struct LineStyle {
    int thick = 2;  // fold line width
    int halo = 1;   // the other colour on each side
    int ring = 9;   // support ring radius
};
LineStyle line_style(int photo_width, int photo_height);

// The legend's font and the rows' geometry at one font scale.
struct LegendFont {
    double scale = 0.0;
    int thickness = 1;
    int line_h = 0;  // one row
    int baseline = 0;
    int key_w = 0;  // the line sample in the key row
    int pad = 6;    // inside the box, and its gap to the cloth and the picture's edge
};
LegendFont legend_font(double scale);

// The key row's labels, drawn before the legend's lines.
const std::vector<std::string>& legend_keys();

// The box around the key row and the lines.
struct BoxSize {
    int width = 0, height = 0;
};
BoxSize legend_box_size(const std::vector<std::string>& legend, const LegendFont& font);

}  // namespace foldcast::compare::detail
