#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>
#include <opencv2/imgproc.hpp>

#include "foldcast/compare/folds.hpp"
#include "foldcast/core/colour.hpp"
#include "hue_line.hpp"
#include "mat_convert.hpp"
#include "robust_stats.hpp"

namespace foldcast::compare {

void validate_supports(const SupportPixels& s, int width, int height) {
    for (const Eigen::Vector2d& p : {s.first, s.second})
        if (!p.allFinite()) throw InputError("supports: a coordinate is not a finite number");
    for (const Eigen::Vector2d& p : {s.first, s.second})
        if (!(p.x() >= 0 && p.y() >= 0 && p.x() <= width - 1 && p.y() <= height - 1))
            throw InputError("supports: point (" + std::to_string(p.x()) + ", " + std::to_string(p.y()) +
                             ") lies outside the " + std::to_string(width) + "x" + std::to_string(height) +
                             " image (x in [0," + std::to_string(width - 1) + "], y in [0," +
                             std::to_string(height - 1) + "])");
    if (s.distance_px() < 2.0)
        throw InputError("supports: the two points are " + std::to_string(s.distance_px()) +
                         " px apart; they must be at least 2 px apart");
}

namespace {

cv::Mat largest_component_filled(const cv::Mat& fg, cv::Point seed) {
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(fg.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    int best = -1;
    double best_area = -1.0;
    for (size_t i = 0; i < contours.size(); ++i) {
        const double area = cv::contourArea(contours[i]);
        const bool has_seed = cv::pointPolygonTest(contours[i], seed, false) >= 0;
        const double score = area + (has_seed ? 1e12 : 0.0);  // the seed's component wins
        if (score > best_area) {
            best_area = score;
            best = static_cast<int>(i);
        }
    }
    cv::Mat out = cv::Mat::zeros(fg.size(), CV_8U);
    if (best >= 0) cv::drawContours(out, contours, best, cv::Scalar(255), cv::FILLED);
    return out;
}

cv::Mat lab_of(const cv::Mat& bgr) {
    cv::Mat lab;
    cv::cvtColor(bgr, lab, cv::COLOR_BGR2Lab);
    return lab;
}

// The median 8-bit CIELAB colour of a rectangle (per channel; the rectangle is not empty).
cv::Vec3d median_lab(const cv::Mat& lab, const cv::Rect& r) {
    cv::Vec3d out(0, 0, 0);
    if (r.area() == 0) return out;
    std::vector<int> v;
    for (int c = 0; c < 3; ++c) {
        v.clear();
        for (int y = r.y; y < r.y + r.height; ++y)
            for (int x = r.x; x < r.x + r.width; ++x) v.push_back(lab.at<cv::Vec3b>(y, x)[c]);
        out[c] = detail::median(v);
    }
    return out;
}

// How far apart two colours are as one cloth's: 8-bit CIELAB distance with lightness at half
// weight, since shading moves a fold's lightness more than its chroma.  A grey cloth before a
// white wall differs by lightness alone.
constexpr double kSameClothLab = 30.0;

double cloth_distance(const cv::Vec3d& p, const cv::Vec3d& q) {
    return std::hypot(0.5 * (p[0] - q[0]), std::hypot(p[1] - q[1], p[2] - q[2]));
}

// The colour of the cloth held just below the supports (0.08-0.2 D below each, 0.08 D wide),
// when it differs from the background's: what the seed's run should be made of.
std::optional<cv::Vec3d> held_colour(const cv::Mat& lab, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                     const cv::Vec3d& background) {
    const double d = (b - a).norm();
    const cv::Rect bounds(0, 0, lab.cols, lab.rows);
    std::array<std::vector<double>, 3> channel;
    for (const Eigen::Vector2d& p : {a, b}) {
        const cv::Rect patch =
            cv::Rect(cv::Point(static_cast<int>(p.x() - 0.04 * d), static_cast<int>(p.y() + 0.08 * d)),
                     cv::Point(static_cast<int>(p.x() + 0.04 * d) + 1, static_cast<int>(p.y() + 0.2 * d) + 1)) &
            bounds;
        for (int y = patch.y; y < patch.y + patch.height; ++y)
            for (int x = patch.x; x < patch.x + patch.width; ++x)
                for (int c = 0; c < 3; ++c) channel[c].push_back(lab.at<cv::Vec3b>(y, x)[c]);
    }
    if (channel[0].size() < 4) return std::nullopt;
    const cv::Vec3d held(detail::median(channel[0]), detail::median(channel[1]), detail::median(channel[2]));
    if (cloth_distance(background, held) < kSameClothLab) return std::nullopt;
    return held;
}

// Where the cloth surely is, to seed GrabCut: a strip on the centre line between the supports
// (a, b, in the small image), where the cloth first shows going down from the support line.
// With slack the top edge sags, by half the support distance D or more, and above it the
// background shows through; so the centre line is read downwards and the strip starts at
// the first run of rows (0.05 D) that differ from the background seen 0.15-0.35 D above the
// support line (which a hanging cloth leaves clear; a collar held at the shoulders may rise a
// little above the line) and agree with each other, and goes on while they do (to 0.25 D).
// The first such run can be a background of its own: a rail or shelf above the line and the
// wall below it, seen between the supports above a deep swag.  So where the cloth held just
// below each support differs in colour from the background above, the first run of that
// cloth's colour is taken (to 1.2 D down), and the first run of any colour only when none has
// it.  Without any run (no background above the line in the picture, or nothing different
// below it) the strip is 0.1-0.35 D below the line, where a cloth with little slack is.
cv::Rect cloth_seed(const cv::Mat& lab, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const double d = (b - a).norm();
    const Eigen::Vector2d mid = 0.5 * (a + b);
    const cv::Rect bounds(0, 0, lab.cols, lab.rows);
    const int x0 = static_cast<int>(mid.x() - 0.05 * d), x1 = static_cast<int>(mid.x() + 0.05 * d) + 1;
    const auto rows = [&](double from, double to) {
        return cv::Rect(cv::Point(x0, static_cast<int>(from)), cv::Point(x1, static_cast<int>(to) + 1)) & bounds;
    };
    const cv::Rect fallback = rows(mid.y() + 0.1 * d, mid.y() + 0.35 * d);
    const cv::Rect above = rows(mid.y() - 0.35 * d, mid.y() - 0.15 * d);
    if (above.area() < 4) return fallback;
    const cv::Vec3d background = median_lab(lab, above);
    constexpr double kDiffers = 12.0, kAgrees = 10.0;  // 8-bit CIELAB distances
    const int run = std::max(2, static_cast<int>(0.05 * d));
    const int first = std::max(0, static_cast<int>(mid.y())), last = lab.rows - run;
    if (first >= last) return fallback;
    // Each row's colour once (the scan below compares every row with several starts).
    std::vector<cv::Vec3d> colour(static_cast<std::size_t>(lab.rows - first));
    for (int y = first; y < lab.rows; ++y) colour[static_cast<std::size_t>(y - first)] = median_lab(lab, rows(y, y));
    const auto at = [&](int y) { return colour[static_cast<std::size_t>(y - first)]; };
    const int longest = std::max(run, static_cast<int>(0.25 * d));
    const std::optional<cv::Vec3d> held = held_colour(lab, a, b, background);
    const int deepest = std::min(last, static_cast<int>(mid.y() + 1.2 * d));
    std::optional<cv::Rect> first_run;
    for (int y = first; y < last; ++y) {
        const cv::Vec3d top = at(y);
        if (cv::norm(top - background) < kDiffers) continue;
        // The rows from y on that differ from the background and agree with row y, to 0.25 D.
        int end = y + 1;
        while (end < std::min(lab.rows, y + longest) && cv::norm(at(end) - background) >= kDiffers &&
               cv::norm(at(end) - top) < kAgrees)
            ++end;
        if (end - y < run) continue;
        const cv::Rect found = rows(y + 1, end - 1);
        if (!held || cloth_distance(median_lab(lab, found), *held) < kSameClothLab) return found;
        if (!first_run) first_run = found;
        if (end >= deepest) break;
        y = end - 1;
    }
    return first_run ? *first_run : fallback;
}

// Pixels of the seed's hue: whose linear-light chromaticity (r, g) = (R, G) / (R + G + B)
// lies within 0.04 of the half-line from white through the seed's median chromaticity, at
// least half as far out from white as the seed's (a warm white wall lies a little way out
// along a red cloth's line).  Shading scales R, G and B alike, and light bounced between a
// fold's walls moves the chromaticity further out along that line (fold_detection.cpp's
// print test), so a fold's shadowed inside and its lit front both match.  Too dark a pixel
// (linear R + G + B < 0.03) has no reliable chromaticity and does not match; nothing matches
// a grey seed, whose hue the background may share.
cv::Mat same_hue(const cv::Mat& bgr, const cv::Rect& seed) {
    cv::Mat same = cv::Mat::zeros(bgr.size(), CV_8U);
    cv::Mat rg(bgr.size(), CV_32FC2);
    for (int y = 0; y < bgr.rows; ++y)
        for (int x = 0; x < bgr.cols; ++x) {
            const cv::Vec3b& p = bgr.at<cv::Vec3b>(y, x);
            const float b = srgb_to_linear(p[0] / 255.0f), g = srgb_to_linear(p[1] / 255.0f),
                        r = srgb_to_linear(p[2] / 255.0f), sum = r + g + b;
            rg.at<cv::Vec2f>(y, x) = sum < 0.03f ? cv::Vec2f(-1.0f, -1.0f) : cv::Vec2f(r / sum, g / sum);
        }
    std::array<std::vector<float>, 2> seen;
    for (int y = seed.y; y < seed.y + seed.height; ++y)
        for (int x = seed.x; x < seed.x + seed.width; ++x)
            if (const cv::Vec2f c = rg.at<cv::Vec2f>(y, x); c[0] >= 0.0f)
                for (std::size_t k = 0; k < 2; ++k) seen[k].push_back(c[int(k)]);
    if (seen[0].empty()) return same;
    const detail::HueLine line(detail::median(seen[0]), detail::median(seen[1]));
    constexpr float kNeutral = 0.02f, kAcross = 0.04f;
    if (line.length < kNeutral) return same;
    for (int y = 0; y < bgr.rows; ++y)
        for (int x = 0; x < bgr.cols; ++x) {
            const cv::Vec2f c = rg.at<cv::Vec2f>(y, x);
            if (c[0] < 0.0f) continue;
            same.at<uchar>(y, x) =
                line.along(c[0], c[1]) >= 0.5f * line.length && line.across(c[0], c[1]) < kAcross ? 255 : 0;
        }
    return same;
}

// The cloth as its own colour shows it: the pixels of the seed's hue (`same`: 255 there)
// connected to the seed, or nothing (an empty Mat) when they also spread above the supports
// (a, b, D apart) or to the picture's left or right edge: then they are background of the
// cloth's colour (or the cloth fills the picture) and say nothing.
struct ColourRegion {
    cv::Mat pixels;  // CV_8U 255, or empty
    int left = 0, right = 0;
};

ColourRegion cloth_colour_region(const cv::Mat& same, const cv::Rect& seed, const Eigen::Vector2d& a,
                                 const Eigen::Vector2d& b) {
    ColourRegion out;
    if (seed.area() == 0) return out;
    cv::Mat open;  // thin bridges to the background cut
    cv::morphologyEx(same, open, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(3, 3)));
    cv::Mat labels, stats, centroids;
    const int count = cv::connectedComponentsWithStats(open, labels, stats, centroids, 8, CV_32S);
    std::vector<int> votes(static_cast<std::size_t>(count), 0);
    for (int y = seed.y; y < seed.y + seed.height; ++y)
        for (int x = seed.x; x < seed.x + seed.width; ++x) ++votes[static_cast<std::size_t>(labels.at<int>(y, x))];
    votes[0] = 0;  // not the cloth's colour
    const int cloth = static_cast<int>(std::max_element(votes.begin(), votes.end()) - votes.begin());
    if (votes[static_cast<std::size_t>(cloth)] == 0) return out;
    const int left = stats.at<int>(cloth, cv::CC_STAT_LEFT), top = stats.at<int>(cloth, cv::CC_STAT_TOP);
    const int right = left + stats.at<int>(cloth, cv::CC_STAT_WIDTH) - 1;
    const double d = (b - a).norm();
    if (left == 0 || right == same.cols - 1 || top < std::min(a.y(), b.y()) - 0.15 * d) return out;
    out.pixels = labels == cloth;
    out.left = left, out.right = right;
    return out;
}

}  // namespace

Image estimate_cloth_mask(const Image& photo, const std::optional<SupportPixels>& supports) {
    if (!supports) {
        Image all(photo.width, photo.height, 1);
        std::fill(all.values.begin(), all.values.end(), 1.0f);
        return all;
    }
    validate_supports(*supports, photo.width, photo.height);
    const cv::Mat full = detail::to_bgr8(photo);
    const double scale = std::min(1.0, 480.0 / std::max(full.cols, full.rows));
    cv::Mat small;
    cv::resize(full, small, cv::Size(), scale, scale, cv::INTER_AREA);

    const Eigen::Vector2d a = supports->first * scale, b = supports->second * scale;
    const double d = (b - a).norm();
    const cv::Rect bounds(0, 0, small.cols, small.rows);
    const cv::Mat lab = lab_of(small);
    const cv::Rect seed = cloth_seed(lab, a, b);
    // The cloth's colour decides the first guess: chroma (CIELAB a, b) near the seed's median
    // (or in the cloth's colour region, below) is probably cloth, the rest probably not.  This
    // keeps a table or wall touching the hem out of the mask.
    std::vector<int> seed_a, seed_b;
    for (int y = seed.y; y < seed.y + seed.height; ++y)
        for (int x = seed.x; x < seed.x + seed.width; ++x) {
            seed_a.push_back(lab.at<cv::Vec3b>(y, x)[1]);
            seed_b.push_back(lab.at<cv::Vec3b>(y, x)[2]);
        }
    if (seed_a.empty()) throw InputError("supports: the cloth below the supports lies outside the image");
    const double ma = detail::median(seed_a), mb = detail::median(seed_b);
    constexpr double kSameCloth = 20.0;  // 8-bit Lab chroma units
    const auto same_cloth = [&](const cv::Vec3b& v) { return std::hypot(v[1] - ma, v[2] - mb) < kSameCloth; };
    cv::Mat same(small.size(), CV_8U);
    for (int y = 0; y < small.rows; ++y)
        for (int x = 0; x < small.cols; ++x) same.at<uchar>(y, x) = same_cloth(lab.at<cv::Vec3b>(y, x)) ? 255 : 0;
    // Where cloth can be: beside the supports by 0.4 D, or as far as the cloth's own colour
    // region reaches, and anywhere below them.  Grippers holding a shirt some way in from its
    // sides leave the sides hanging beside them, and a rectangle that cuts through the cloth
    // there makes GrabCut learn the cloth's colour as background (a panel reaching 0.6 D beside
    // its supports came out as its darker inner face alone).  A cloth may hang several times D
    // (a tall panel on close supports); below the supports the colour prior, not the
    // rectangle, keeps a table or a floor out.  The colour region joins the prior: a seed on
    // a fold's saturated shadowed inside then does not leave the lit front to the background.
    int rect_left = static_cast<int>(std::min(a.x(), b.x()) - 0.4 * d);
    int rect_right = static_cast<int>(std::max(a.x(), b.x()) + 0.4 * d);
    if (const ColourRegion region = cloth_colour_region(same_hue(small, seed), seed, a, b); !region.pixels.empty()) {
        const int margin = static_cast<int>(0.05 * d) + 1;
        rect_left = std::min(rect_left, region.left - margin);
        rect_right = std::max(rect_right, region.right + margin);
        same |= region.pixels;
    }
    const cv::Rect rect = cv::Rect(cv::Point(rect_left, static_cast<int>(std::min(a.y(), b.y()) - 0.08 * d)),
                                   cv::Point(rect_right, small.rows)) &
                          bounds;
    cv::Mat labels(small.size(), CV_8U, cv::Scalar(cv::GC_BGD));
    for (int y = rect.y; y < rect.y + rect.height; ++y)
        for (int x = rect.x; x < rect.x + rect.width; ++x)
            labels.at<uchar>(y, x) = same.at<uchar>(y, x) ? cv::GC_PR_FGD : cv::GC_PR_BGD;
    labels(seed).setTo(cv::GC_FGD);
    cv::Mat bgd_model, fgd_model;
    cv::setRNGSeed(12345);  // GrabCut's GMM initialisation draws from OpenCV's RNG
    cv::grabCut(small, labels, rect, bgd_model, fgd_model, 5, cv::GC_INIT_WITH_MASK);
    cv::Mat fg = (labels == cv::GC_FGD) | (labels == cv::GC_PR_FGD);
    cv::morphologyEx(fg, fg, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
    fg = largest_component_filled(fg, (seed.tl() + seed.br()) / 2);
    cv::Mat up;
    cv::resize(fg, up, full.size(), 0, 0, cv::INTER_LINEAR);
    cv::Mat binary = up > 127;
    cv::Mat values;
    binary.convertTo(values, CV_32F, 1.0 / 255.0);
    return detail::from_mat(values);
}

Image read_mask(const std::filesystem::path& path, int width, int height) {
    const Image raw = read_image(path);
    if (raw.width != width || raw.height != height)
        throw InputError("mask '" + path.string() + "': size " + std::to_string(raw.width) + "x" +
                         std::to_string(raw.height) + " differs from the photo's " + std::to_string(width) + "x" +
                         std::to_string(height));
    Image mask(width, height, 1);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) mask.at(x, y, 0) = raw.at(x, y, 0) > 0.5f ? 1.0f : 0.0f;
    if (std::none_of(mask.values.begin(), mask.values.end(), [](float v) { return v > 0.5f; }))
        throw InputError("mask '" + path.string() + "': no pixel above half scale, so no cloth; white marks the cloth");
    return mask;
}

}  // namespace foldcast::compare
