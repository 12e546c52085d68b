#include "overlay_style.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace foldcast::compare::detail {

LineStyle line_style(int photo_width, int photo_height) {
    const double diag = std::hypot(photo_width, photo_height);
    LineStyle s;
    // About 0.2 % of the diagonal (3 px on a 1280 px wide photo), at least 2 px so that an
    // anti-aliased line still reaches its full colour.
    s.thick = std::max(2, static_cast<int>(std::lround(diag / 500.0)));
    s.halo = std::max(1, s.thick / 2);
    s.ring = 3 * s.thick + 3;
    return s;
}

LegendFont legend_font(double scale) {
    LegendFont f;
    f.scale = scale;
    f.thickness = scale > 0.6 ? 2 : 1;
    const cv::Size ag = cv::getTextSize("Ag", cv::FONT_HERSHEY_SIMPLEX, scale, f.thickness, &f.baseline);
    // Spacing grows with the text (the 6 px padding and 5 px leading of a 0.42 font, the
    // shared photos'), so that a large legend is not cramped.
    f.pad = std::max(6, static_cast<int>(std::lround(14 * scale)));
    f.line_h = ag.height + f.baseline + std::max(5, static_cast<int>(std::lround(12 * scale)));
    f.key_w = static_cast<int>(30 * scale / 0.5);
    return f;
}

const std::vector<std::string>& legend_keys() {
    static const std::vector<std::string> keys{"crest", "valley", "support"};
    return keys;
}

BoxSize legend_box_size(const std::vector<std::string>& legend, const LegendFont& f) {
    int baseline = 0, text_w = 0, key_row_w = 0;
    for (const auto& t : legend)
        text_w = std::max(text_w, cv::getTextSize(t, cv::FONT_HERSHEY_SIMPLEX, f.scale, f.thickness, &baseline).width);
    for (const auto& k : legend_keys())
        key_row_w += f.key_w + f.pad +
                     cv::getTextSize(k, cv::FONT_HERSHEY_SIMPLEX, f.scale, f.thickness, &baseline).width + 2 * f.pad;
    const int rows = 1 + static_cast<int>(legend.size());
    return {std::max(text_w, key_row_w) + 2 * f.pad, rows * f.line_h + 2 * f.pad};
}

}  // namespace foldcast::compare::detail
