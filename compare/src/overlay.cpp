#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "foldcast/compare/legend_layout.hpp"
#include "foldcast/compare/overlay.hpp"
#include "mat_convert.hpp"
#include "overlay_style.hpp"

namespace foldcast::compare {

Eigen::Vector2d ClothToImage::operator()(double x_m, double y_m) const {
    const Eigen::Vector3d p = h * Eigen::Vector3d(x_m, y_m, 1.0);
    return p.head<2>() / p.z();
}

ClothToImage similarity_from_supports(const SupportPixels& s, double span_m) {
    if (!(span_m > 0))
        throw InputError("support span must be > 0 m (width - 2 x inset), got " + std::to_string(span_m));
    const Eigen::Vector2d d = s.second - s.first;
    const double scale = d.norm() / span_m;
    const Eigen::Vector2d ex = d.normalized();  // cloth +x in pixels
    const Eigen::Vector2d ey(ex.y(), -ex.x());  // cloth +y (up): picture "up" when supports are level
    const Eigen::Vector2d mid = 0.5 * (s.first + s.second);
    ClothToImage m;
    m.h << scale * ex.x(), scale * ey.x(), mid.x(),  //
        scale * ex.y(), scale * ey.y(), mid.y(),     //
        0, 0, 1;
    m.px_per_m = scale;
    return m;
}

ClothToImage homography_from_corners(const std::array<Eigen::Vector2d, 4>& c, double span_m, double height_m) {
    const double l = span_m, hh = height_m;
    const cv::Point2f src[4] = {{static_cast<float>(-l / 2), 0.0f},
                                {static_cast<float>(l / 2), 0.0f},
                                {static_cast<float>(l / 2), static_cast<float>(-hh)},
                                {static_cast<float>(-l / 2), static_cast<float>(-hh)}};
    cv::Point2f dst[4];
    for (int i = 0; i < 4; ++i) dst[i] = cv::Point2f(static_cast<float>(c[i].x()), static_cast<float>(c[i].y()));
    // Degenerate quadrilaterals (three points on a line) have no homography.
    for (int i = 0; i < 4; ++i) {
        const cv::Point2f a = dst[(i + 1) % 4] - dst[i], b = dst[(i + 2) % 4] - dst[i];
        if (std::abs(a.cross(b)) < 1.0f)
            throw InputError(
                "corners: three of the four points are (nearly) on one line; give support 1, support 2, "
                "hem below support 2, hem below support 1");
    }
    const cv::Mat H = cv::getPerspectiveTransform(src, dst);
    ClothToImage m;
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) m.h(r, k) = H.at<double>(r, k);
    m.px_per_m = (c[1] - c[0]).norm() / l;
    return m;
}

std::vector<PredictedLine> project_fold_lines(const std::vector<drape::FoldLine>& lines, int folds,
                                              const ClothToImage& map) {
    std::vector<PredictedLine> out;
    for (const auto& line : lines) {
        PredictedLine p;
        p.index = line.index;
        p.sign = line.sign;
        p.top_edge = line.index == folds;
        for (const auto& q : line.points) p.points_px.push_back(map(q.x(), q.y()));  // orthographic: z dropped
        out.push_back(std::move(p));
    }
    return out;
}

std::vector<PredictedLine> clip_to_cloth(const std::vector<PredictedLine>& lines, const Image& mask) {
    auto on_cloth = [&](const Eigen::Vector2d& p) {
        const long x = std::lround(p.x()), y = std::lround(p.y());
        return x >= 0 && y >= 0 && x < mask.width && y < mask.height && mask.at(int(x), int(y), 0) > 0.5f;
    };
    std::vector<PredictedLine> out;
    for (const auto& line : lines) {
        if (line.top_edge) continue;
        PredictedLine piece{line.index, line.sign, false, {}};
        Eigen::Vector2d last_on_cloth(0, 0);
        auto flush = [&] {
            double length = 0.0;
            for (size_t i = 1; i < piece.points_px.size(); ++i)
                length += (piece.points_px[i] - piece.points_px[i - 1]).norm();
            if (length >= 2.0) out.push_back(piece);
            piece.points_px.clear();
        };
        // Walk each segment in steps of at most 1 px so that the cut falls within a pixel of
        // the mask's edge.
        for (size_t i = 0; i < line.points_px.size(); ++i) {
            const Eigen::Vector2d a = i == 0 ? line.points_px[0] : line.points_px[i - 1], b = line.points_px[i];
            const int steps = i == 0 ? 1 : std::max(1, static_cast<int>(std::ceil((b - a).norm())));
            for (int k = 1; k <= steps; ++k) {
                const Eigen::Vector2d p = a + (b - a) * (double(k) / steps);
                if (on_cloth(p)) {
                    if (piece.points_px.empty() || k == steps) piece.points_px.push_back(p);
                    last_on_cloth = p;
                } else if (!piece.points_px.empty()) {
                    if (piece.points_px.back() != last_on_cloth) piece.points_px.push_back(last_on_cloth);
                    flush();
                }
            }
        }
        flush();
    }
    return out;
}

namespace {

std::vector<cv::Point> to_fixed(const std::vector<Eigen::Vector2d>& pts) {
    // 4 fractional bits for anti-aliased sub-pixel drawing.
    std::vector<cv::Point> out;
    for (const auto& p : pts) out.emplace_back(cvRound(p.x() * 16), cvRound(p.y() * 16));
    return out;
}

void dashed(cv::Mat& canvas, const std::vector<Eigen::Vector2d>& pts, double dash_px, const cv::Scalar& colour,
            int thickness) {
    if (pts.size() < 2 || !(dash_px > 0)) return;
    std::vector<double> arc(pts.size(), 0.0);  // cumulative length at each vertex
    for (size_t i = 1; i < pts.size(); ++i) arc[i] = arc[i - 1] + (pts[i] - pts[i - 1]).norm();
    auto at = [&](double s) {
        const size_t i = std::min<size_t>(std::upper_bound(arc.begin(), arc.end(), s) - arc.begin(), pts.size() - 1);
        const size_t j = i == 0 ? 1 : i;
        const double seg = arc[j] - arc[j - 1];
        const double t = seg > 0 ? std::clamp((s - arc[j - 1]) / seg, 0.0, 1.0) : 0.0;
        return Eigen::Vector2d(pts[j - 1] + t * (pts[j] - pts[j - 1]));
    };
    const int dashes = static_cast<int>(std::ceil(arc.back() / (2 * dash_px)));
    for (int k = 0; k < dashes; ++k) {
        const double s0 = 2 * dash_px * k, s1 = std::min(arc.back(), s0 + dash_px);
        std::vector<Eigen::Vector2d> piece{at(s0)};
        for (size_t i = 0; i < pts.size(); ++i)
            if (arc[i] > s0 && arc[i] < s1) piece.push_back(pts[i]);
        piece.push_back(at(s1));
        cv::polylines(canvas, to_fixed(piece), false, colour, thickness, cv::LINE_AA, 4);
    }
}

}  // namespace

Image draw_overlay(const Image& photo, const std::vector<PredictedLine>& lines, const SupportPixels& supports,
                   const std::vector<std::string>& legend, const Image& mask) {
    return draw_overlay(photo, lines, supports, legend,
                        layout_legend(legend, photo.width, photo.height, mask, lines, supports));
}

Image draw_overlay(const Image& photo, const std::vector<PredictedLine>& lines, const SupportPixels& supports,
                   const std::vector<std::string>& legend, const LegendLayout& layout) {
    cv::Mat canvas = detail::to_bgr8(photo);
    const detail::LineStyle st = detail::line_style(canvas.cols, canvas.rows);
    const int thick = st.thick, halo = st.halo;
    const cv::Scalar black(0, 0, 0), white(255, 255, 255);
    for (const auto& line : lines) {
        if (line.top_edge) continue;
        const auto fixed = to_fixed(line.points_px);
        if (line.sign > 0) {
            cv::polylines(canvas, fixed, false, white, thick + 2 * halo, cv::LINE_AA, 4);
            cv::polylines(canvas, fixed, false, black, thick, cv::LINE_AA, 4);
        } else {
            const double dash = 4.0 * thick + 4.0;
            dashed(canvas, line.points_px, dash, black, thick + 2 * halo);
            dashed(canvas, line.points_px, dash, white, thick);
        }
    }
    const int r = st.ring;
    for (const auto& s : {supports.first, supports.second}) {
        const cv::Point c(cvRound(s.x()), cvRound(s.y()));
        cv::circle(canvas, c, r + 1, black, thick + 2, cv::LINE_AA);
        cv::circle(canvas, c, r, cv::Scalar(255, 0, 255), thick, cv::LINE_AA);
        cv::drawMarker(canvas, c, cv::Scalar(255, 0, 255), cv::MARKER_CROSS, r, std::max(1, thick / 2), cv::LINE_AA);
    }
    // The band, when the layout needs one: white, the photo untouched at the top left.
    if (layout.picture_width > canvas.cols || layout.picture_height > canvas.rows)
        cv::copyMakeBorder(canvas, canvas, 0, std::max(0, layout.picture_height - canvas.rows), 0,
                           std::max(0, layout.picture_width - canvas.cols), cv::BORDER_CONSTANT, white);
    const cv::Rect box =
        cv::Rect(layout.x, layout.y, layout.width, layout.height) & cv::Rect(0, 0, canvas.cols, canvas.rows);
    if (box.area() == 0) return detail::from_bgr8(canvas);

    // A white box, one key row (crest, valley, support) then the numbers.
    const detail::LegendFont f = detail::legend_font(layout.font_scale);
    const int font = cv::FONT_HERSHEY_SIMPLEX, pad = f.pad, line_h = f.line_h, key_w = f.key_w;
    const auto& keys = detail::legend_keys();
    int baseline = 0;
    cv::Mat roi = canvas(box);
    cv::Mat tint(roi.size(), roi.type(), white);
    cv::addWeighted(roi, 0.15, tint, 0.85, 0.0, roi);
    cv::rectangle(canvas, box, black, 1);
    const int text_dy = line_h / 2 - f.baseline - 1;
    {
        const int y = box.y + pad + line_h / 2;
        int x = box.x + pad;
        for (size_t k = 0; k < keys.size(); ++k) {
            const int x1 = x + key_w;
            if (k == 0) {
                cv::line(canvas, {x, y}, {x1, y}, white, thick + 2 * halo, cv::LINE_AA);
                cv::line(canvas, {x, y}, {x1, y}, black, thick, cv::LINE_AA);
            } else if (k == 1) {
                dashed(canvas, {Eigen::Vector2d(x, y), Eigen::Vector2d(x1, y)}, key_w / 5.0, black, thick + 2 * halo);
                dashed(canvas, {Eigen::Vector2d(x, y), Eigen::Vector2d(x1, y)}, key_w / 5.0, white, thick);
            } else {
                cv::circle(canvas, {(x + x1) / 2, y}, line_h / 3, cv::Scalar(255, 0, 255), thick, cv::LINE_AA);
            }
            cv::putText(canvas, keys[k], {x1 + pad, y + text_dy}, font, f.scale, black, f.thickness, cv::LINE_AA);
            x = x1 + pad + cv::getTextSize(keys[k], font, f.scale, f.thickness, &baseline).width + 2 * pad;
        }
    }
    for (size_t i = 0; i < legend.size(); ++i) {
        const int y = box.y + pad + static_cast<int>(i + 1) * line_h + line_h / 2;
        cv::putText(canvas, legend[i], {box.x + pad, y + text_dy}, font, f.scale, black, f.thickness, cv::LINE_AA);
    }
    return detail::from_bgr8(canvas);
}

}  // namespace foldcast::compare
