// Agreement between predicted and detected fold lines, and the parameter search on it.
#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <opencv2/imgproc.hpp>

#include "foldcast/compare/overlay.hpp"
#include "mat_convert.hpp"

namespace foldcast::compare {
namespace {

// Points every ~1 px along a polyline.
std::vector<Eigen::Vector2d> resample(const std::vector<Eigen::Vector2d>& pts) {
    std::vector<Eigen::Vector2d> out;
    for (size_t i = 1; i < pts.size(); ++i) {
        const double len = (pts[i] - pts[i - 1]).norm();
        const int steps = std::max(1, static_cast<int>(std::ceil(len)));
        for (int k = 0; k < steps; ++k) out.push_back(pts[i - 1] + (pts[i] - pts[i - 1]) * (double(k) / steps));
    }
    if (!pts.empty()) out.push_back(pts.back());
    return out;
}

bool inside(const cv::Mat& region, const Eigen::Vector2d& p) {
    const int x = cvRound(p.x()), y = cvRound(p.y());
    return x >= 0 && y >= 0 && x < region.cols && y < region.rows && region.at<uchar>(y, x);
}

// Distance (px) from every pixel to the nearest of `points`.
cv::Mat distance_to(const std::vector<Eigen::Vector2d>& points, cv::Size size) {
    cv::Mat free(size, CV_8U, cv::Scalar(255));
    for (const auto& p : points) {
        const int x = cvRound(p.x()), y = cvRound(p.y());
        if (x >= 0 && y >= 0 && x < size.width && y < size.height) free.at<uchar>(y, x) = 0;
    }
    cv::Mat dist;
    cv::distanceTransform(free, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    return dist;
}

}  // namespace

double agreement(double f1, int count_error) { return 0.5 * (f1 + 1.0 / (1.0 + std::abs(count_error))); }

FoldScore score_folds(const std::vector<PredictedLine>& predicted, const FoldDetection& detection,
                      const CentreLine& centre, double px_per_m, double tolerance_px) {
    if (!(std::isfinite(tolerance_px) && tolerance_px > 0))
        throw InputError("fold score: tolerance = " + std::to_string(tolerance_px) +
                         " px; it must be a finite distance > 0");
    if (!(std::isfinite(px_per_m) && px_per_m > 0))
        throw InputError("fold score: scale = " + std::to_string(px_per_m) + " px/m; it must be finite and > 0");
    FoldScore s;
    s.tolerance_px = tolerance_px;
    s.tolerance_cm = 100.0 * tolerance_px / px_per_m;
    const double truncation_px = 5.0 * tolerance_px;
    s.truncation_cm = 100.0 * truncation_px / px_per_m;
    cv::Mat region;
    detail::to_mat(detection.search_region).convertTo(region, CV_8U, 255.0);

    std::vector<Eigen::Vector2d> pred, det;
    std::set<int> fold_indices;
    for (const auto& line : predicted) {
        if (line.top_edge) continue;
        fold_indices.insert(line.index);
        for (const auto& p : resample(line.points_px))
            if (inside(region, p)) pred.push_back(p);
    }
    s.predicted_folds = static_cast<int>(fold_indices.size());
    s.measured_folds = centre.folds;
    s.count_error = s.predicted_folds - s.measured_folds;
    s.detected_lines = static_cast<int>(detection.folds.size());
    for (const auto& f : detection.folds)
        for (const auto& p : resample(f.points_px)) det.push_back(p);

    if (pred.empty() || det.empty()) {
        s.chamfer_cm = pred.empty() && det.empty() ? 0.0 : s.truncation_cm;
        s.agreement = agreement(0.0, s.count_error);
        return s;
    }
    const cv::Size size(region.cols, region.rows);
    const cv::Mat to_det = distance_to(det, size), to_pred = distance_to(pred, size);
    auto sum_near = [&](const std::vector<Eigen::Vector2d>& pts, const cv::Mat& dist, double& truncated_sum) {
        int near = 0;
        truncated_sum = 0.0;
        for (const auto& p : pts) {
            const int x = std::clamp(cvRound(p.x()), 0, size.width - 1),
                      y = std::clamp(cvRound(p.y()), 0, size.height - 1);
            const double d = dist.at<float>(y, x);
            truncated_sum += std::min(d, truncation_px);
            near += d <= tolerance_px;
        }
        return near;
    };
    double pred_sum = 0.0, det_sum = 0.0;
    s.precision = double(sum_near(pred, to_det, pred_sum)) / pred.size();
    s.recall = double(sum_near(det, to_pred, det_sum)) / det.size();
    s.f1 = s.precision + s.recall > 0 ? 2 * s.precision * s.recall / (s.precision + s.recall) : 0.0;
    s.agreement = agreement(s.f1, s.count_error);
    s.chamfer_cm = 100.0 * 0.5 * (pred_sum / pred.size() + det_sum / det.size()) / px_per_m;
    return s;
}

namespace {

// The profiles from the support line down to the lowest cloth pixel of the centre fibre: the
// band's mean shading and mean luma over its cloth pixels, whether the band is cloth and
// whether it crosses a print's outline, and the first and last depth on cloth.
struct CentreProfiles {
    std::vector<double> shading, luma;
    std::vector<bool> on_cloth, on_print;
    int first = -1, last = -1;
};

CentreProfiles centre_profiles(const FoldDetection& detection, const Eigen::Vector2d& mid, const Eigen::Vector2d& down,
                               const Eigen::Vector2d& ex, int offsets) {
    const Image& shading = detection.shading;
    auto value = [&](const Image& img, const Eigen::Vector2d& p, float* v) {
        const long x = std::lround(p.x()), y = std::lround(p.y());
        if (x < 0 || y < 0 || x >= img.width || y >= img.height) return false;
        *v = img.at(int(x), int(y), 0);
        return true;
    };
    CentreProfiles out;
    const int max_depth = static_cast<int>(std::ceil(std::hypot(shading.width, shading.height)));
    for (int depth = 0; depth < max_depth; ++depth) {
        double sum = 0.0, luma_sum = 0.0;
        int n = 0, printed = 0;
        for (int k = -offsets; k <= offsets; ++k) {
            const Eigen::Vector2d p = mid + depth * down + k * ex;
            float m = 0.0f, v = 0.0f, l = 0.0f, pm = 0.0f;
            if (value(detection.mask, p, &m) && m > 0.5f && value(shading, p, &v) && value(detection.luma, p, &l)) {
                if (!detection.print_outline.empty() && value(detection.print_outline, p, &pm) && pm > 0.5f) {
                    ++printed;
                    continue;
                }
                sum += v;
                luma_sum += l;
                ++n;
            }
        }
        const bool cloth = 2 * (n + printed) > 2 * offsets + 1;  // most of the band is cloth
        out.shading.push_back(n > 0 ? sum / n : 0.0);
        out.luma.push_back(n > 0 ? luma_sum / n : 0.0);
        out.on_cloth.push_back(cloth);
        // A print's outline is filled in: no fold can be read there (inside a print of one
        // colour the shading is read, scaled to the cloth's brightness).
        out.on_print.push_back(printed > 0);
        if (cloth) {
            if (out.first < 0) out.first = depth;
            out.last = depth;
        }
    }
    return out;
}

// Gaussian smoothing of a profile, reflected ends.
std::vector<double> smoothed_profile(const std::vector<double>& q, double sigma) {
    const int n = static_cast<int>(q.size());
    const int radius = static_cast<int>(std::ceil(3 * sigma));
    std::vector<double> kernel(2 * radius + 1);
    double ksum = 0.0;
    for (int k = -radius; k <= radius; ++k) ksum += kernel[k + radius] = std::exp(-0.5 * k * k / (sigma * sigma));
    std::vector<double> result(n, 0.0);
    for (int i = 0; i < n; ++i) {
        double acc = 0.0;
        for (int k = -radius; k <= radius; ++k) {
            int j = i + k;
            while (j < 0 || j >= n) j = j < 0 ? -j : 2 * (n - 1) - j;
            acc += kernel[k + radius] * q[std::clamp(j, 0, n - 1)];
        }
        result[i] = acc / ksum;
    }
    return result;
}

struct CentreExtremum {
    int depth;
    int sign;
    double strength;
    double sigma;
};

// One extremum per place (the strongest scale), then strict alternation: two crests in
// a row without a valley between them are one broad crest.
std::vector<CentreExtremum> alternating_extrema(std::vector<CentreExtremum> found) {
    std::sort(found.begin(), found.end(), [](const CentreExtremum& a, const CentreExtremum& b) {
        return a.depth != b.depth ? a.depth < b.depth : a.strength > b.strength;
    });
    std::vector<CentreExtremum> merged;
    for (const auto& e : found) {
        if (!merged.empty() && (e.depth - merged.back().depth < 2.0 * std::max(e.sigma, merged.back().sigma) ||
                                e.sign == merged.back().sign)) {
            if (e.strength > merged.back().strength) merged.back() = e;
            continue;
        }
        merged.push_back(e);
    }
    return merged;
}

}  // namespace

CentreLine measure_centre_line(const FoldDetection& detection, const SupportPixels& supports) {
    CentreLine out;
    // The relative shading, on which the thresholds are, and the luma, on which the floors are.
    const Image& shading = detection.shading;
    const Image& luma = detection.luma;
    if (shading.empty() || luma.empty() || detection.sigmas_px.empty()) return out;
    const double d = supports.distance_px();
    const Eigen::Vector2d ex = (supports.second - supports.first) / d, down(-ex.y(), ex.x());
    const Eigen::Vector2d mid = 0.5 * (supports.first + supports.second);
    const double half_band = std::max(1.0, 0.02 * d);
    const int offsets = static_cast<int>(std::floor(half_band));
    const CentreProfiles profiles = centre_profiles(detection, mid, down, ex, offsets);
    const std::vector<double>& profile = profiles.shading;
    const std::vector<double>& luma_profile = profiles.luma;
    const std::vector<bool>& on_cloth = profiles.on_cloth;
    const std::vector<bool>& on_print = profiles.on_print;
    const int first = profiles.first, last = profiles.last;
    if (first < 0) return out;
    out.top_edge_depth_px = first;
    out.hem_depth_px = last;
    // Away from the top edge and the hem by 2 sigma_max, as the 2-D search region is from
    // the outline: the silhouette's contrast is not a fold.
    const double sigma_max = *std::max_element(detection.sigmas_px.begin(), detection.sigmas_px.end());
    const int margin = static_cast<int>(std::ceil(2.0 * sigma_max));
    const int from = first + margin, to = last - margin;
    if (to - from < 3) return out;
    // Between first and last the profile may have gaps (holes in the band): fill by the
    // nearest cloth value so that the smoothing does not see the background.
    std::vector<double> p(profile.begin() + first, profile.begin() + last + 1);
    std::vector<double> pl(luma_profile.begin() + first, luma_profile.begin() + last + 1);
    for (size_t i = 1; i < p.size(); ++i)
        if (!on_cloth[first + i] || on_print[first + i]) p[i] = p[i - 1], pl[i] = pl[i - 1];
    // Within 2 sigma_max of a print or a gap the profile is not the cloth's own.
    std::vector<bool> unreadable(p.size(), false);
    for (size_t i = 0; i < p.size(); ++i)
        if (!on_cloth[first + i] || on_print[first + i])
            for (int k = -margin; k <= margin; ++k)
                if (int(i) + k >= 0 && int(i) + k < int(p.size())) unreadable[size_t(int(i) + k)] = true;

    // As the 2-D detector's hysteresis: an extremum under the high threshold but over the low
    // one counts where a detected line of its sign crosses the fibre there (the line was
    // seeded by a stronger stretch elsewhere).  On glossy cloth the highlights raise the
    // region's median response, hence the high threshold, above the folds' own strength on
    // the fibre while the lines through them are found.
    const auto on_detected_line = [&](int depth, int sign, double sigma) {
        const Eigen::Vector2d at = mid + depth * down;
        const double reach = std::max(2.0, sigma);
        for (const DetectedFold& f : detection.folds) {
            if (f.sign != sign) continue;
            for (const Eigen::Vector2d& q : f.points_px)
                if (std::abs((q - at).dot(down)) <= reach && std::abs((q - at).dot(ex)) <= half_band) return true;
        }
        return false;
    };
    std::vector<CentreExtremum> found;
    const int n = static_cast<int>(p.size());
    const auto second_difference = [](const std::vector<double>& q, int i) { return q[i + 1] - 2 * q[i] + q[i - 1]; };
    for (double sigma : detection.sigmas_px) {
        const std::vector<double> smooth = smoothed_profile(p, sigma), smooth_luma = smoothed_profile(pl, sigma);
        const double norm = std::pow(sigma * sigma, 0.75);  // the detector's gamma-normalisation
        for (int i = std::max(1, from - first); i < std::min(n - 1, to - first + 1); ++i) {
            if (unreadable[size_t(i)]) continue;
            const double d1a = smooth[i] - smooth[i - 1], d1b = smooth[i + 1] - smooth[i];
            if (!(d1a * d1b <= 0) || (d1a == 0 && d1b == 0)) continue;
            const double d2 = second_difference(smooth, i);
            const double strength = norm * std::abs(d2);
            const double luma_strength = norm * std::abs(second_difference(smooth_luma, i));
            const int sign = d2 < 0 ? 1 : -1;
            const bool high = strength >= detection.high_threshold && luma_strength >= detection.high_floor;
            const bool low = strength >= detection.low_threshold && luma_strength >= detection.low_floor;
            if (!high && !(low && on_detected_line(first + i, sign, sigma))) continue;
            found.push_back({first + i, sign, strength, sigma});
        }
    }
    const std::vector<CentreExtremum> merged = alternating_extrema(std::move(found));
    for (const auto& e : merged) {
        out.depths_px.push_back(e.depth);
        out.signs.push_back(e.sign);
    }
    out.folds = static_cast<int>(merged.size());
    if (out.folds >= 2 && out.depths_px.front() > 0)
        out.Q = std::pow(out.depths_px.back() / out.depths_px.front(), 1.0 / (out.folds - 1));
    else if (out.folds == 1 && out.top_edge_depth_px >= 2.0)
        out.Q = out.depths_px.back() / out.top_edge_depth_px;
    return out;
}

}  // namespace foldcast::compare
