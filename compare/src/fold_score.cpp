// Agreement between predicted and detected fold lines, and the parameter search on it.
#include <cmath>
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

FoldScore score_folds(const std::vector<PredictedLine>& predicted, const FoldDetection& detection, double px_per_m,
                      double tolerance_px) {
    FoldScore s;
    s.tolerance_px = tolerance_px;
    s.tolerance_cm = 100.0 * tolerance_px / px_per_m;
    const double truncation_px = 5.0 * tolerance_px;
    s.truncation_cm = 100.0 * truncation_px / px_per_m;
    cv::Mat region;
    detail::to_mat(detection.search_region).convertTo(region, CV_8U, 255.0);

    std::vector<Eigen::Vector2d> pred, det;
    for (const auto& line : predicted) {
        if (line.top_edge) continue;
        ++s.predicted_folds;
        for (const auto& p : resample(line.points_px))
            if (inside(region, p)) pred.push_back(p);
    }
    s.detected_folds = static_cast<int>(detection.folds.size());
    for (const auto& f : detection.folds)
        for (const auto& p : resample(f.points_px)) det.push_back(p);

    if (pred.empty() || det.empty()) {
        s.chamfer_cm = pred.empty() && det.empty() ? 0.0 : s.truncation_cm;
        return s;
    }
    const cv::Size size(region.cols, region.rows);
    const cv::Mat to_det = distance_to(det, size), to_pred = distance_to(pred, size);
    auto sum_near = [&](const std::vector<Eigen::Vector2d>& pts, const cv::Mat& dist, double& truncated_sum) {
        int near = 0;
        truncated_sum = 0.0;
        for (const auto& p : pts) {
            const int x = std::clamp(cvRound(p.x()), 0, size.width - 1), y = std::clamp(cvRound(p.y()), 0, size.height - 1);
            const double d = dist.at<float>(y, x);
            truncated_sum += std::min(d, truncation_px);
            near += d <= tolerance_px;
        }
        return near;
    };
    double pred_sum = 0.0, det_sum = 0.0;
    s.recall = double(sum_near(pred, to_det, pred_sum)) / pred.size();
    s.precision = double(sum_near(det, to_pred, det_sum)) / det.size();
    s.f1 = s.precision + s.recall > 0 ? 2 * s.precision * s.recall / (s.precision + s.recall) : 0.0;
    s.chamfer_cm = 100.0 * 0.5 * (pred_sum / pred.size() + det_sum / det.size()) / px_per_m;
    return s;
}

FitResult fit_folds(const drape::ClothParams& start, const std::function<ClothToImage(const drape::ClothParams&)>& map_for,
                    const FoldDetection& detection, double tolerance_px, bool keep_span) {
    const double span = start.support_span_m();
    FitResult best;
    bool have = false;
    for (int i = 0; i < 10; ++i)
        for (int j = -4; j <= 4; ++j) {  // load constant x 2^(0.75 j)
            drape::ClothParams p = start;
            if (keep_span) {
                p.inset_m = 0.4 * span * i / 9.0;
                p.width_m = span + 2.0 * p.inset_m;
            } else {
                p.inset_m = 0.4 * start.width_m * i / 9.0;
            }
            p.load_constant = start.load_constant * std::pow(2.0, 0.75 * j);
            drape::FoldSolution solution;
            ClothToImage map;
            try {
                solution = drape::solve_folds(p);
                map = map_for(p);
            } catch (const InputError&) {
                continue;  // outside the model's valid range
            }
            const auto lines = project_fold_lines(drape::fold_lines(p, solution), solution.folds, map);
            const FoldScore score = score_folds(lines, detection, map.px_per_m, tolerance_px);
            ++best.evaluated;
            // F1 first: the chamfer distance alone rewards predicting many dense lines.
            const bool better = !have || score.f1 > best.score.f1 + 1e-9 ||
                                (std::abs(score.f1 - best.score.f1) <= 1e-9 && score.chamfer_cm < best.score.chamfer_cm);
            if (better) {
                const int evaluated = best.evaluated;
                best = {p, solution, score, evaluated};
                have = true;
            }
        }
    if (!have) throw InputError("--fit: no parameter set in the search range could be solved");
    return best;
}

}  // namespace foldcast::compare
