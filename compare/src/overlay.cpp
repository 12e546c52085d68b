#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "foldcast/compare/overlay.hpp"
#include "mat_convert.hpp"

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
    cv::Mat canvas = detail::to_bgr8(photo);
    const double diag = std::hypot(canvas.cols, canvas.rows);
    // About 0.2 % of the diagonal (3 px on a 1280 px wide photo), at least 2 px so that an
    // anti-aliased line still reaches its full colour.
    const int thick = std::max(2, static_cast<int>(std::lround(diag / 500.0)));
    const cv::Scalar black(0, 0, 0), white(255, 255, 255);
    const int halo = std::max(1, thick / 2);
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
    const int r = 3 * thick + 3;
    for (const auto& s : {supports.first, supports.second}) {
        const cv::Point c(cvRound(s.x()), cvRound(s.y()));
        cv::circle(canvas, c, r + 1, black, thick + 2, cv::LINE_AA);
        cv::circle(canvas, c, r, cv::Scalar(255, 0, 255), thick, cv::LINE_AA);
        cv::drawMarker(canvas, c, cv::Scalar(255, 0, 255), cv::MARKER_CROSS, r, std::max(1, thick / 2), cv::LINE_AA);
    }

    // Legend: a white box, one key row (crest, valley, support) then the numbers; the font
    // shrinks (to 0.3) until the box is at most half the picture wide.
    const int font = cv::FONT_HERSHEY_SIMPLEX;
    const std::vector<std::string> keys{"crest", "valley", "support"};
    double font_scale = std::max(0.35, diag / 3000.0);
    int text_thick = 1, baseline = 0, line_h = 0, key_w = 0, text_w = 0, key_row_w = 0;
    const int pad = 6;
    for (;; font_scale *= 0.92) {
        text_thick = font_scale > 0.6 ? 2 : 1;
        line_h = cv::getTextSize("Ag", font, font_scale, text_thick, &baseline).height + baseline + 5;
        key_w = static_cast<int>(30 * font_scale / 0.5);
        text_w = 0;
        for (const auto& t : legend)
            text_w = std::max(text_w, cv::getTextSize(t, font, font_scale, text_thick, &baseline).width);
        key_row_w = 0;
        for (const auto& k : keys)
            key_row_w += key_w + pad + cv::getTextSize(k, font, font_scale, text_thick, &baseline).width + 2 * pad;
        if (std::max(text_w, key_row_w) + 2 * pad <= canvas.cols / 2 || font_scale < 0.3) break;
    }
    const int rows = 1 + static_cast<int>(legend.size());
    const int box_w = std::min(canvas.cols - 2 * pad, std::max(text_w, key_row_w) + 2 * pad);
    const int box_h = std::min(canvas.rows - 2 * pad, rows * line_h + 2 * pad);
    if (box_w < 1 || box_h < 1) return detail::from_bgr8(canvas);  // no room for a legend
    // Where the box covers the least cloth, then the fewest line points and no support;
    // candidates on a grid of steps a quarter of the box, scanned in a fixed order.
    cv::Mat cloth_sum;
    {
        cv::Mat cloth = cv::Mat::zeros(canvas.size(), CV_8U);
        if (!mask.empty() && mask.width == canvas.cols && mask.height == canvas.rows) {
            cv::Mat m;
            detail::to_mat(mask).convertTo(m, CV_8U, 255.0);
            cloth = m > 127;
            cloth /= 255;
        }
        cv::integral(cloth, cloth_sum, CV_32S);
    }
    cv::Mat line_mask = cv::Mat::zeros(canvas.size(), CV_8U);
    for (const auto& line : lines)
        for (const auto& p : line.points_px) {
            const int x = cvRound(p.x()), y = cvRound(p.y());
            if (x >= 0 && y >= 0 && x < canvas.cols && y < canvas.rows) line_mask.at<uchar>(y, x) = 1;
        }
    cv::Mat line_sum;
    cv::integral(line_mask, line_sum, CV_32S);
    auto count = [](const cv::Mat& sum, const cv::Rect& r) {
        return sum.at<int>(r.y + r.height, r.x + r.width) - sum.at<int>(r.y, r.x + r.width) -
               sum.at<int>(r.y + r.height, r.x) + sum.at<int>(r.y, r.x);
    };
    cv::Rect box(pad, pad, box_w, box_h);
    double fewest = -1.0;
    const int step_x = std::max(1, box_w / 4), step_y = std::max(1, box_h / 4);
    for (int y = pad; y + box_h <= canvas.rows - pad; y += step_y)
        for (int x = pad; x + box_w <= canvas.cols - pad; x += step_x) {
            const cv::Rect candidate(x, y, box_w, box_h);
            double cost = 100.0 * count(cloth_sum, candidate) + 10.0 * count(line_sum, candidate);
            for (const auto& p : {supports.first, supports.second})
                if (candidate.contains(cv::Point(cvRound(p.x()), cvRound(p.y())))) cost += 1e9;
            if (fewest < 0 || cost < fewest) {
                fewest = cost;
                box = candidate;
            }
        }
    cv::Mat roi = canvas(box);
    cv::Mat tint(roi.size(), roi.type(), white);
    cv::addWeighted(roi, 0.15, tint, 0.85, 0.0, roi);
    cv::rectangle(canvas, box, black, 1);
    const int text_dy = line_h / 2 - baseline - 1;
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
            cv::putText(canvas, keys[k], {x1 + pad, y + text_dy}, font, font_scale, black, text_thick, cv::LINE_AA);
            x = x1 + pad + cv::getTextSize(keys[k], font, font_scale, text_thick, &baseline).width + 2 * pad;
        }
    }
    for (size_t i = 0; i < legend.size(); ++i) {
        const int y = box.y + pad + static_cast<int>(i + 1) * line_h + line_h / 2;
        cv::putText(canvas, legend[i], {box.x + pad, y + text_dy}, font, font_scale, black, text_thick, cv::LINE_AA);
    }
    return detail::from_bgr8(canvas);
}

}  // namespace foldcast::compare
