#include "foldcast/compare/legend_layout.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <opencv2/imgproc.hpp>

#include "mat_convert.hpp"
#include "overlay_style.hpp"

namespace foldcast::compare {
namespace {

// 1 where the legend must not go: the cloth, the lines at their drawn width with halo, the
// support rings; grown by `gap` so that the box does not touch them.
cv::Mat keep_clear(int width, int height, const Image& mask, const std::vector<PredictedLine>& lines,
                   const SupportPixels& supports, int gap) {
    cv::Mat clear = cv::Mat::zeros(height, width, CV_8U);
    if (!mask.empty() && mask.width == width && mask.height == height) {
        const cv::Mat m = detail::to_mat(mask);
        cv::Mat cloth;
        cv::extractChannel(m, cloth, 0);
        clear.setTo(1, cloth > 0.5f);
    }
    const detail::LineStyle st = detail::line_style(width, height);
    for (const auto& line : lines) {
        std::vector<cv::Point> pts;
        for (const auto& p : line.points_px) pts.emplace_back(cvRound(p.x()), cvRound(p.y()));
        cv::polylines(clear, pts, false, cv::Scalar(1), st.thick + 2 * st.halo + 2);
    }
    // The ring's outline (radius + 1, width thick + 2) and its black rim.
    const int ring = st.ring + 2 + st.thick / 2 + 2;
    for (const auto& s : {supports.first, supports.second})
        cv::circle(clear, {cvRound(s.x()), cvRound(s.y())}, ring, cv::Scalar(1), cv::FILLED);
    if (gap > 0) cv::dilate(clear, clear, cv::getStructuringElement(cv::MORPH_RECT, {2 * gap + 1, 2 * gap + 1}));
    return clear;
}

// The clear position of a w x h box nearest a corner of the picture (then the first in
// rows from the top): a legend tucked into a corner is where readers look for it.
std::optional<cv::Point> clear_place(const cv::Mat& clear_sum, int width, int height, int w, int h, int edge) {
    std::optional<cv::Point> best;
    int nearest = 0;
    for (int y = edge; y + h <= height - edge; ++y)
        for (int x = edge; x + w <= width - edge; ++x) {
            const int covered = clear_sum.at<int>(y + h, x + w) - clear_sum.at<int>(y, x + w) -
                                clear_sum.at<int>(y + h, x) + clear_sum.at<int>(y, x);
            if (covered) continue;
            const int to_corner = std::min(x - edge, width - edge - x - w) + std::min(y - edge, height - edge - y - h);
            if (!best || to_corner < nearest) best = cv::Point(x, y), nearest = to_corner;
        }
    return best;
}

}  // namespace

const char* to_string(LegendLayout::Place place) {
    switch (place) {
        case LegendLayout::Place::photo:
            return "photo";
        case LegendLayout::Place::band_right:
            return "band right";
        case LegendLayout::Place::band_below:
            return "band below";
    }
    return "photo";
}

LegendLayout layout_legend(const std::vector<std::string>& legend, int photo_width, int photo_height, const Image& mask,
                           const std::vector<PredictedLine>& lines, const SupportPixels& supports) {
    // Text in proportion to the photo (0.42 on the 1104 x 621 shared photos), so that it
    // reads alike whatever the photo's resolution.
    const double start = std::max(kLegendMinFontScale, std::hypot(photo_width, photo_height) / 3000.0);
    const double smallest = std::max(kLegendMinFontScale, 0.5 * start);
    const detail::LegendFont start_font = detail::legend_font(start);
    cv::Mat clear_sum;
    cv::integral(keep_clear(photo_width, photo_height, mask, lines, supports, start_font.pad), clear_sum, CV_32S);

    LegendLayout out;
    out.picture_width = photo_width, out.picture_height = photo_height;
    for (double scale = start;; scale = std::max(smallest, 0.92 * scale)) {
        const detail::LegendFont f = detail::legend_font(scale);
        const detail::BoxSize size = detail::legend_box_size(legend, f);
        if (const auto at = clear_place(clear_sum, photo_width, photo_height, size.width, size.height, f.pad)) {
            out.x = at->x, out.y = at->y, out.width = size.width, out.height = size.height;
            out.font_scale = scale;
            return out;
        }
        if (scale <= smallest) break;
    }

    // No clear place: the legend beside the photo rather than over the cloth or unreadably small.
    const detail::BoxSize size = detail::legend_box_size(legend, start_font);
    const int band_w = size.width + 2 * start_font.pad, band_h = size.height + 2 * start_font.pad;
    const long right = static_cast<long>(photo_width + band_w) * std::max(photo_height, band_h);
    const long below = static_cast<long>(std::max(photo_width, band_w)) * (photo_height + band_h);
    out.font_scale = start;
    out.width = size.width, out.height = size.height;
    if (right < below) {
        out.place = LegendLayout::Place::band_right;
        out.picture_width = photo_width + band_w, out.picture_height = std::max(photo_height, band_h);
        out.x = photo_width + start_font.pad, out.y = start_font.pad;
    } else {
        out.place = LegendLayout::Place::band_below;
        out.picture_width = std::max(photo_width, band_w), out.picture_height = photo_height + band_h;
        out.x = start_font.pad, out.y = photo_height + start_font.pad;
    }
    return out;
}

}  // namespace foldcast::compare
