// Multi-scale Hessian ridge/valley detection (Lindeberg, "Edge detection and ridge detection
// with automatic scale selection", IJCV 1998): at each scale t = sigma^2 the Hessian of the
// smoothed luminance has eigenvalues l1 (largest magnitude) and l2; the ridge strength
// t^gamma (|l1| - |l2|) is large across a line and small on blobs and flat areas; its sign
// says bright ridge (l1 < 0) or dark valley (l1 > 0).  Each pixel keeps its strongest scale.
#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>

#include "foldcast/compare/folds.hpp"
#include "foldcast/core/colour.hpp"
#include "hue_line.hpp"
#include "mat_convert.hpp"
#include "robust_stats.hpp"

namespace foldcast::compare {

using detail::HueLine;
using detail::median;
using detail::quantile;

double DetectedFold::length_px() const {
    double length = 0.0;
    for (size_t i = 1; i < points_px.size(); ++i) length += (points_px[i] - points_px[i - 1]).norm();
    return length;
}

namespace {

struct RidgeField {
    cv::Mat strength;             // CV_32F, >= 0
    cv::Mat sign;                 // CV_8S, +1 bright ridge, -1 dark valley
    cv::Mat nx, ny;               // CV_32F unit normal across the line
    cv::Mat scale;                // CV_8U index of the strongest scale
    std::vector<cv::Mat> smooth;  // luminance smoothed at each scale
};

// Strength only (the luma's, for the noise floor) or also each pixel's sign, normal, scale and
// the smoothed images (what tracing lines needs).
enum class RidgeParts { strength, all };

RidgeField ridge_field(const cv::Mat& luma, const std::vector<double>& sigmas, double gamma,
                       RidgeParts parts = RidgeParts::all) {
    RidgeField f;
    const bool all = parts == RidgeParts::all;
    f.strength = cv::Mat::zeros(luma.size(), CV_32F);
    if (all) {
        f.sign = cv::Mat::zeros(luma.size(), CV_8S);
        f.nx = cv::Mat::zeros(luma.size(), CV_32F);
        f.ny = cv::Mat::zeros(luma.size(), CV_32F);
        f.scale = cv::Mat::zeros(luma.size(), CV_8U);
    }
    for (size_t si = 0; si < sigmas.size(); ++si) {
        const double sigma = sigmas[si];
        cv::Mat smooth, lxx, lyy, lxy;
        cv::GaussianBlur(luma, smooth, cv::Size(), sigma, sigma, cv::BORDER_REFLECT);
        cv::Sobel(smooth, lxx, CV_32F, 2, 0, 3, 0.25, 0, cv::BORDER_REFLECT);
        cv::Sobel(smooth, lyy, CV_32F, 0, 2, 3, 0.25, 0, cv::BORDER_REFLECT);
        cv::Sobel(smooth, lxy, CV_32F, 1, 1, 3, 0.25, 0, cv::BORDER_REFLECT);
        const float norm = static_cast<float>(std::pow(sigma * sigma, gamma));
        for (int y = 0; y < luma.rows; ++y)
            for (int x = 0; x < luma.cols; ++x) {
                const float a = lxx.at<float>(y, x), c = lyy.at<float>(y, x), b = lxy.at<float>(y, x);
                const float mean = 0.5f * (a + c), radius = std::hypot(0.5f * (a - c), b);
                const float lp = mean + radius, lm = mean - radius;  // lp >= lm
                const bool plus_dominant = std::abs(lp) >= std::abs(lm);
                const float l1 = plus_dominant ? lp : lm, l2 = plus_dominant ? lm : lp;
                const float s = norm * (std::abs(l1) - std::abs(l2));
                if (s <= f.strength.at<float>(y, x)) continue;
                f.strength.at<float>(y, x) = s;
                if (!all) continue;
                // Eigenvector of lp is at angle 0.5 atan2(2b, a - c); that of lm is perpendicular.
                float theta = 0.5f * std::atan2(2.0f * b, a - c);
                if (!plus_dominant) theta += 1.5707963f;
                f.sign.at<schar>(y, x) = l1 < 0 ? 1 : -1;
                f.nx.at<float>(y, x) = std::cos(theta);
                f.ny.at<float>(y, x) = std::sin(theta);
                f.scale.at<uchar>(y, x) = static_cast<uchar>(si);
            }
        if (all) f.smooth.push_back(smooth);
    }
    return f;
}

float sample(const cv::Mat& m, float x, float y) {
    x = std::clamp(x, 0.0f, static_cast<float>(m.cols - 1));
    y = std::clamp(y, 0.0f, static_cast<float>(m.rows - 1));
    const int x0 = std::min(static_cast<int>(x), m.cols - 2 < 0 ? 0 : m.cols - 2);
    const int y0 = std::min(static_cast<int>(y), m.rows - 2 < 0 ? 0 : m.rows - 2);
    const int x1 = std::min(x0 + 1, m.cols - 1), y1 = std::min(y0 + 1, m.rows - 1);
    const float fx = x - x0, fy = y - y0;
    return (1 - fx) * (1 - fy) * m.at<float>(y0, x0) + fx * (1 - fy) * m.at<float>(y0, x1) +
           (1 - fx) * fy * m.at<float>(y1, x0) + fx * fy * m.at<float>(y1, x1);
}

// Print colours are told apart on the chromaticity median-filtered over 5x5 px: a thin
// crease darkens a print by a pixel or two, and JPEG's coarse chroma moves such pixels'
// colour; the filtered colour is the print's.  Each pixel whose filtered colour lies
// farther than `limit` from the cloth's (mr, mg) joins the nearest group whose mean lies
// within `limit`, else starts one (at most kMaxGroups; the rest cannot be normalised); a
// second pass assigns every such pixel to the nearest final mean.  A pixel `printed` by its
// own colour but not by the filtered one (a dot, a thin stroke) cannot be normalised.
struct PrintColours {
    cv::Mat label;  // CV_32S: 0 cloth, k >= 1 group k - 1, -1 printed but in no group
    int groups = 0;
};

PrintColours group_print_colours(const cv::Mat& chroma_r, const cv::Mat& chroma_g, const cv::Mat& cloth,
                                 const cv::Mat& printed, float mr, float mg, float limit) {
    cv::Mat r_filtered, g_filtered;
    cv::medianBlur(chroma_r, r_filtered, 5);
    cv::medianBlur(chroma_g, g_filtered, 5);
    cv::Mat coloured = cv::Mat::zeros(cloth.size(), CV_8U);
    for (int y = 0; y < cloth.rows; ++y)
        for (int x = 0; x < cloth.cols; ++x)
            coloured.at<uchar>(y, x) = cloth.at<uchar>(y, x) && std::hypot(r_filtered.at<float>(y, x) - mr,
                                                                           g_filtered.at<float>(y, x) - mg) > limit;
    constexpr int kMaxGroups = 16;
    struct Group {
        double r = 0, g = 0;
        long n = 0;
    };
    std::vector<Group> groups;
    auto nearest = [&](float r, float g) {
        int best = -1;
        double best_d = limit;
        for (size_t k = 0; k < groups.size(); ++k) {
            const double d = std::hypot(r - groups[k].r / groups[k].n, g - groups[k].g / groups[k].n);
            if (d <= best_d) {
                best_d = d;
                best = int(k);
            }
        }
        return best;
    };
    for (int y = 0; y < cloth.rows; ++y)
        for (int x = 0; x < cloth.cols; ++x) {
            if (!coloured.at<uchar>(y, x)) continue;
            const float r = r_filtered.at<float>(y, x), g = g_filtered.at<float>(y, x);
            int k = nearest(r, g);
            if (k < 0 && int(groups.size()) < kMaxGroups) {
                groups.push_back({});
                k = int(groups.size()) - 1;
            }
            if (k >= 0) {
                groups[size_t(k)].r += r;
                groups[size_t(k)].g += g;
                ++groups[size_t(k)].n;
            }
        }
    PrintColours out{cv::Mat(cloth.size(), CV_32S, cv::Scalar(0)), int(groups.size())};
    for (int y = 0; y < cloth.rows; ++y)
        for (int x = 0; x < cloth.cols; ++x)
            if (coloured.at<uchar>(y, x)) {
                const int k = nearest(r_filtered.at<float>(y, x), g_filtered.at<float>(y, x));
                out.label.at<int>(y, x) = k < 0 ? -1 : k + 1;
            } else if (printed.at<uchar>(y, x)) {
                out.label.at<int>(y, x) = -1;
            }
    return out;
}

// Where the colour changes: a pixel of the cloth that has no group or whose 8-neighbourhood
// (on the cloth) holds another label.  CV_8U 255.
cv::Mat colour_changes(const cv::Mat& label, const cv::Mat& cloth) {
    cv::Mat change = cv::Mat::zeros(cloth.size(), CV_8U);
    for (int y = 0; y < cloth.rows; ++y)
        for (int x = 0; x < cloth.cols; ++x) {
            if (!cloth.at<uchar>(y, x)) continue;
            const int l = label.at<int>(y, x);
            bool edge = l < 0;
            for (int dy = -1; dy <= 1 && !edge; ++dy)
                for (int dx = -1; dx <= 1 && !edge; ++dx) {
                    const int qx = x + dx, qy = y + dy;
                    if (qx < 0 || qy < 0 || qx >= cloth.cols || qy >= cloth.rows || !cloth.at<uchar>(qy, qx)) continue;
                    edge = label.at<int>(qy, qx) != l;
                }
            change.at<uchar>(y, x) = edge ? 255 : 0;
        }
    return change;
}

// Sheen is not print.  A pile or glossy cloth (velvet, satin) reflects the light's own colour
// at grazing angles, so its highlights mix the cloth's colour with white: their chromaticity
// lies on the segment from the cloth's to white, farther from the cloth's than its spread
// allows, as a white or pale print's does.  What tells them apart is how the colour changes at
// the region's outline: a print's ink stops within a pixel or two, so the colour jumps across
// it by about as much as the print differs from the cloth; a highlight fades out over many
// pixels as the surface turns.  So a connected region of `printed` pixels is sheen, and is
// dropped, when (1) nine in ten of its pixels lie on that segment (within `limit` of it, t in
// (0, 1.15], t the fraction of the way from the cloth's chromaticity to white) and (2) across
// its outline t changes by less than 0.4 of the region's own (the median over its outline
// pixels of t's range over 5x5 px, against the region's 90th percentile of t).
void drop_sheen(cv::Mat& printed, const cv::Mat& chroma_r, const cv::Mat& chroma_g, float mr, float mg, float limit) {
    const HueLine line(mr, mg);
    if (line.length < 2.0f * limit) return;  // a near-white cloth: its highlights are not told from it
    cv::Mat t(printed.size(), CV_32F), on_segment(printed.size(), CV_8U);
    for (int y = 0; y < printed.rows; ++y)
        for (int x = 0; x < printed.cols; ++x) {
            const float r = chroma_r.at<float>(y, x), g = chroma_g.at<float>(y, x);
            const float towards_white = 1.0f - line.along(r, g) / line.length;
            t.at<float>(y, x) = towards_white;
            on_segment.at<uchar>(y, x) = line.across(r, g) < limit && towards_white > 0.0f && towards_white <= 1.15f;
        }
    cv::Mat high, low;
    const cv::Mat box = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5));
    cv::dilate(t, high, box);
    cv::erode(t, low, box);
    cv::Mat labels;
    const int count = cv::connectedComponents(printed, labels, 8, CV_32S);
    struct Region {
        long pixels = 0, on_segment = 0;
        std::vector<float> t, outline_range;
    };
    std::vector<Region> regions(static_cast<std::size_t>(count));
    for (int y = 0; y < printed.rows; ++y)
        for (int x = 0; x < printed.cols; ++x) {
            const int l = labels.at<int>(y, x);
            if (l == 0) continue;
            Region& r = regions[static_cast<std::size_t>(l)];
            ++r.pixels;
            r.on_segment += on_segment.at<uchar>(y, x);
            r.t.push_back(t.at<float>(y, x));
            const bool outline = x == 0 || y == 0 || x + 1 == printed.cols || y + 1 == printed.rows ||
                                 labels.at<int>(y, x - 1) != l || labels.at<int>(y, x + 1) != l ||
                                 labels.at<int>(y - 1, x) != l || labels.at<int>(y + 1, x) != l;
            if (outline) r.outline_range.push_back(high.at<float>(y, x) - low.at<float>(y, x));
        }
    std::vector<bool> sheen(static_cast<std::size_t>(count), false);
    for (std::size_t l = 1; l < regions.size(); ++l) {
        Region& r = regions[l];
        if (r.pixels == 0 || r.outline_range.empty() || 10 * r.on_segment < 9 * r.pixels) continue;
        sheen[l] = quantile(r.outline_range, 0.5) < 0.4f * quantile(r.t, 0.9);
    }
    for (int y = 0; y < printed.rows; ++y)
        for (int x = 0; x < printed.cols; ++x)
            if (sheen[static_cast<std::size_t>(labels.at<int>(y, x))]) printed.at<uchar>(y, x) = 0;
}

// Printed motifs (letters, logos, dots): pixels whose linear-light chromaticity
// (R, G) / (R + G + B) lies far from the cloth's median.  Shading (a fold turning away from
// the light) scales R, G and B alike and leaves the chromaticity where it is; a print of
// another colour moves it.  The limit adapts to the cloth's own spread (its weave, JPEG
// noise, coloured bounce light): 6 robust standard deviations, at least 0.04.  Pixels too
// dark for a stable ratio (linear sum < 0.03) take the colour of the nearest pixel that is
// not (a dark crease across a print is still the print).  Opened by 3x3 to drop specks.
//
// A fold that crosses a print still shades it: inside a print of one colour the brightness
// is the print's albedo times the same shading as on the cloth.  So the print pixels are
// grouped by colour (chromaticity within the same limit of a group's mean), and each
// group's luma is scaled by (the cloth's median luma / the group's median luma): the
// shading image is then continuous across the print and a crease through it stays visible.
// What cannot be read is where the colour changes (a print's blurred outline, one print
// colour against another) and a group too small for its median (dots, thin strokes):
// `outline`, dilated by `grow_px`, is filled in from around it and left out of the search.
struct PrintLayers {
    cv::Mat prints;   // CV_8U 255: printed (opened), dilated by grow_px
    cv::Mat outline;  // CV_8U 255: where the reflectance changes or cannot be normalised, dilated
    cv::Mat gain;     // CV_32F: luma x gain = shading (1 on the cloth)
};

PrintLayers print_layers(const Image& photo, const cv::Mat& cloth, int grow_px) {
    const cv::Mat rgb = detail::rgb_of(photo);
    PrintLayers out;
    out.prints = cv::Mat::zeros(rgb.size(), CV_8U);
    out.outline = cv::Mat::zeros(rgb.size(), CV_8U);
    out.gain = cv::Mat::ones(rgb.size(), CV_32F);
    cv::Mat chroma_r(rgb.size(), CV_32F), chroma_g(rgb.size(), CV_32F), dark(rgb.size(), CV_8U);
    for (int y = 0; y < rgb.rows; ++y)
        for (int x = 0; x < rgb.cols; ++x) {
            const cv::Vec3f v = rgb.at<cv::Vec3f>(y, x);
            const float r = srgb_to_linear(std::clamp(v[0], 0.0f, 1.0f)),
                        g = srgb_to_linear(std::clamp(v[1], 0.0f, 1.0f)),
                        b = srgb_to_linear(std::clamp(v[2], 0.0f, 1.0f));
            const float sum = r + g + b;
            dark.at<uchar>(y, x) = sum < 0.03f;
            chroma_r.at<float>(y, x) = sum > 0 ? r / sum : 1.0f / 3.0f;
            chroma_g.at<float>(y, x) = sum > 0 ? g / sum : 1.0f / 3.0f;
        }
    std::vector<float> rs, gs;
    for (int y = 0; y < rgb.rows; ++y)
        for (int x = 0; x < rgb.cols; ++x)
            if (cloth.at<uchar>(y, x) && !dark.at<uchar>(y, x)) {
                rs.push_back(chroma_r.at<float>(y, x));
                gs.push_back(chroma_g.at<float>(y, x));
            }
    if (rs.empty()) return out;
    // Dark pixels take the chromaticity of the nearest pixel that is not dark.
    if (cv::countNonZero(dark) > 0) {
        cv::Mat dist, labels;
        cv::distanceTransform(dark, dist, labels, cv::DIST_L2, cv::DIST_MASK_5, cv::DIST_LABEL_PIXEL);
        std::vector<cv::Point> source(1);  // label -> the non-dark pixel it names (labels start at 1)
        for (int y = 0; y < rgb.rows; ++y)
            for (int x = 0; x < rgb.cols; ++x)
                if (!dark.at<uchar>(y, x)) source.emplace_back(x, y);
        for (int y = 0; y < rgb.rows; ++y)
            for (int x = 0; x < rgb.cols; ++x) {
                if (!dark.at<uchar>(y, x)) continue;
                const int label = labels.at<int>(y, x);
                if (label <= 0 || label >= int(source.size())) continue;
                const cv::Point q = source[size_t(label)];
                chroma_r.at<float>(y, x) = chroma_r.at<float>(q);
                chroma_g.at<float>(y, x) = chroma_g.at<float>(q);
            }
    }
    const float mr = median(rs), mg = median(gs);
    // Light that bounces between the walls of a fold takes the cloth's colour again at each
    // bounce, so a fold's shaded valley is the cloth's colour, more saturated: its
    // chromaticity lies further out along the line from white through the cloth's.  A print's
    // lies anywhere else (another hue, or nearer white).  So the distance that marks a print
    // is to the half-line from the cloth's chromaticity away from white, not to the point
    // (on a saturated red cloth in a studio render the point's distance marked every fold's
    // valley as print).  A near-white cloth has no such direction: the point it is.
    constexpr float kNeutral = 0.02f;
    const HueLine line(mr, mg);
    const auto print_distance = [&](float r, float g) {
        if (line.length < kNeutral || line.along(r, g) <= line.length) return std::hypot(r - mr, g - mg);
        return line.across(r, g);  // across the half-line
    };
    cv::Mat distance(rgb.size(), CV_32F);
    std::vector<float> ds;
    for (int y = 0; y < rgb.rows; ++y)
        for (int x = 0; x < rgb.cols; ++x) {
            const float r = chroma_r.at<float>(y, x), g = chroma_g.at<float>(y, x);
            distance.at<float>(y, x) = print_distance(r, g);
            if (cloth.at<uchar>(y, x) && !dark.at<uchar>(y, x)) ds.push_back(std::hypot(r - mr, g - mg));
        }
    // The limit: the spread of the cloth's chromaticity about its median (the photo's noise,
    // its white balance across the cloth), from the distance to the point.
    const float median_d = median(ds);
    for (float& d : ds) d = std::abs(d - median_d);
    const float limit = std::max(0.04f, median_d + 6.0f * 1.4826f * median(ds));
    cv::Mat printed = cv::Mat::zeros(rgb.size(), CV_8U);
    for (int y = 0; y < rgb.rows; ++y)
        for (int x = 0; x < rgb.cols; ++x)
            printed.at<uchar>(y, x) = cloth.at<uchar>(y, x) && distance.at<float>(y, x) > limit ? 255 : 0;
    cv::morphologyEx(printed, printed, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
    drop_sheen(printed, chroma_r, chroma_g, mr, mg, limit);
    const cv::Mat grow =
        cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * grow_px + 1, 2 * grow_px + 1));  // 1x1: none
    cv::dilate(printed, out.prints, grow);
    if (cv::countNonZero(printed) == 0) return out;

    const PrintColours colours = group_print_colours(chroma_r, chroma_g, cloth, printed, mr, mg, limit);
    const cv::Mat& label = colours.label;
    cv::dilate(colour_changes(label, cloth), out.outline, grow);
    // Each colour's median luma away from its outline (the cloth is label 0); a group with
    // fewer than kMinCore such pixels is left to the outline as a whole.
    constexpr size_t kMinCore = 50;
    const cv::Mat luma = detail::luma_of(photo);
    std::vector<std::vector<float>> core(std::size_t(colours.groups) + 1);
    for (int y = 0; y < rgb.rows; ++y)
        for (int x = 0; x < rgb.cols; ++x) {
            const int l = label.at<int>(y, x);
            if (cloth.at<uchar>(y, x) && l >= 0 && !out.outline.at<uchar>(y, x))
                core[size_t(l)].push_back(luma.at<float>(y, x));
        }
    const float cloth_luma = core[0].empty() ? 0.0f : median(core[0]);
    std::vector<float> gain(core.size(), 1.0f);
    std::vector<bool> readable(core.size(), true);
    for (size_t k = 1; k < core.size(); ++k) {
        const float m = core[k].size() >= kMinCore ? median(core[k]) : 0.0f;
        readable[k] = cloth_luma > 0 && m > 1e-3f;
        gain[k] = readable[k] ? cloth_luma / m : 1.0f;
    }
    cv::Mat unreadable = cv::Mat::zeros(rgb.size(), CV_8U);
    for (int y = 0; y < rgb.rows; ++y)
        for (int x = 0; x < rgb.cols; ++x) {
            const int l = label.at<int>(y, x);
            if (l < 0 || !readable[size_t(l)])
                unreadable.at<uchar>(y, x) = 255;
            else
                out.gain.at<float>(y, x) = gain[size_t(l)];
        }
    cv::dilate(unreadable, unreadable, grow);
    out.outline |= unreadable;
    out.outline &= out.prints;  // only around prints (the dilation may reach past them)
    return out;
}

// The shading the ridge filter measures: log((L + k m) / m), L the luma (prints scaled,
// outlines filled in), m the cloth's median luma, k = 0.5.  A fold scales the light a patch
// of cloth gets, so what it changes is a ratio: on log luma the same fold responds as strongly
// on a dark cloth as on a light one, and the threshold taken from the cloth's own response
// (4 x its median) does not follow the cloth's albedo.  The log also compresses a glossy
// cloth's highlights, many times the cloth's brightness, which on luma itself raised that
// threshold above the folds (silk charmeuse on the studio scene).  The offset k m bounds the
// gain of the log, 1 / (L + k m), at 1 / (k m) in the darkest pixels (a deep valley's floor,
// a photo's noise near black) where the log would stretch a code value without limit.  k
// from the studio scene's ten looks (docs/compare.md): silk measures 2 / 3 / 3 / 1 folds at k
// = 0.1 / 0.25 / 0.5 / 1 (a larger k is nearly linear over a highlight, a smaller one
// stretches the noise of the dark valleys), every other look the same at all four.
cv::Mat relative_shading(const cv::Mat& luma, const cv::Mat& cloth) {
    constexpr float kOffset = 0.5f;
    std::vector<float> values;
    for (int y = 0; y < luma.rows; ++y)
        for (int x = 0; x < luma.cols; ++x)
            if (cloth.at<uchar>(y, x)) values.push_back(luma.at<float>(y, x));
    const float typical = std::max(median(values), 1e-3f);  // a black cloth: no ratio to read
    cv::Mat shading;
    cv::log(cv::max(luma, 0.0f) / typical + kOffset, shading);
    return shading;
}

// Where a fold's band lies across the line: the midpoint of the two places where the
// brightness profile across it (along the normal, averaged over 3 px along the line) crosses
// half the band's depth.  The extremum of the brightness, and with it the strongest ridge
// response, sits off the band's middle when the walls are unequal (a valley seen obliquely)
// or its floor is lit (a valley's floor faces the sky, the walls shade its feet): the
// half-level crossings are set by the whole band, not by its darkest or brightest pixel.
// The profile is read from the finest smoothing; `reach_px` bounds where the extremum may
// be (the point's own scale), the shoulders are looked for out to 2.5 times that.  Returns
// the offset along the normal, or nothing when the profile holds no band (too shallow).
std::optional<float> band_centre(const cv::Mat& image, float x, float y, float nx, float ny, double reach_px,
                                 int sign) {
    constexpr float kStepPx = 0.25f;
    const int half = static_cast<int>(std::ceil(2.5 * reach_px / kStepPx));
    const int extremum_half = static_cast<int>(std::ceil(reach_px / kStepPx));
    std::vector<float> q(2 * half + 1);
    for (int i = -half; i <= half; ++i) {
        const float t = i * kStepPx;
        float sum = 0.0f;
        for (int u = -1; u <= 1; ++u) sum += sample(image, x + t * nx - u * ny, y + t * ny + u * nx);
        q[i + half] = sign * sum / 3.0f;  // the band is a peak of q: crest bright, valley dark
    }
    int peak = half - extremum_half;
    for (int i = half - extremum_half; i <= half + extremum_half; ++i)
        if (q[i] > q[peak]) peak = i;
    const int left = static_cast<int>(std::min_element(q.begin(), q.begin() + peak + 1) - q.begin());
    const int right = static_cast<int>(std::min_element(q.begin() + peak, q.end()) - q.begin());
    const float floor_level = std::max(q[left], q[right]);
    if (!(q[peak] - floor_level > 1e-4f)) return std::nullopt;
    const float level = 0.5f * (q[peak] + floor_level);
    // From each shoulder inwards to the first sample at or above the level; linear between.
    int a = left;
    while (q[a + 1] < level) ++a;
    int b = right;
    while (q[b - 1] < level) --b;
    const float t_left = (a - half + (level - q[a]) / (q[a + 1] - q[a])) * kStepPx;
    const float t_right = (b - half - (level - q[b]) / (q[b - 1] - q[b])) * kStepPx;
    const float centre = 0.5f * (t_left + t_right);
    if (!(std::abs(centre) <= reach_px)) return std::nullopt;
    return centre;
}

const int kDx[8] = {1, 1, 0, -1, -1, -1, 0, 1};
const int kDy[8] = {0, 1, 1, 1, 0, -1, -1, -1};

}  // namespace

void validate(const FoldDetectionOptions& o) {
    auto check = [](bool ok, const std::string& name, double value, const char* allowed) {
        if (!ok)
            throw InputError("fold detection: " + name + " = " + std::to_string(value) + " is not allowed; " + allowed);
    };
    for (double s : o.sigmas_px)
        check(std::isfinite(s) && s > 0, "sigmas_px", s, "each scale must be a finite number > 0");
    check(std::isfinite(o.gamma) && o.gamma >= 0 && o.gamma <= 2, "gamma", o.gamma, "allowed: 0 to 2");
    check(std::isfinite(o.high_threshold) && o.high_threshold >= 0, "high_threshold", o.high_threshold,
          "allowed: >= 0 (0 = automatic)");
    check(std::isfinite(o.low_ratio) && o.low_ratio > 0 && o.low_ratio <= 1, "low_ratio", o.low_ratio,
          "allowed: (0, 1]");
    check(std::isfinite(o.min_length_px) && o.min_length_px >= 0, "min_length_px", o.min_length_px,
          "allowed: a finite length >= 0 px (0 = automatic)");
}

namespace {

// The cloth, the luma the ridge filter reads and the prints' layers.  The luma is the
// shading: each print colour scaled to the cloth's brightness (a fold through a print stays
// visible), and where the colour changes filled in from around it (Telea), so that the
// outlines of letters and logos are not ridges at any scale.
struct SearchImages {
    cv::Mat cloth, luma, prints, unreadable;
};

SearchImages search_images(const Image& photo, const Image& mask, const FoldDetectionOptions& options,
                           double finest_sigma) {
    SearchImages in;
    detail::to_mat(mask).convertTo(in.cloth, CV_8U, 255.0);
    in.cloth = in.cloth > 127;
    in.luma = detail::luma_of(photo);
    in.prints = cv::Mat::zeros(in.luma.size(), CV_8U), in.unreadable = in.prints.clone();
    if (!(options.exclude_prints && photo.channels >= 3)) return in;
    const PrintLayers layers = print_layers(photo, in.cloth, static_cast<int>(std::ceil(finest_sigma)) + 1);
    in.prints = layers.prints;
    in.unreadable = layers.outline;
    in.luma = in.luma.mul(layers.gain);
    if (cv::countNonZero(in.unreadable) > 0) {
        // Through 16 bits: OpenCV's Telea fills 8- and 16-bit images (float ones pass
        // through unchanged in 4.6); scaled so that a gain above 1 does not clip.
        double top = 1.0;
        cv::minMaxLoc(in.luma, nullptr, &top);
        top = std::max(1.0, top);
        cv::Mat luma16, filled;
        in.luma.convertTo(luma16, CV_16U, 65535.0 / top);
        cv::inpaint(luma16, in.unreadable, filled, 3.0, cv::INPAINT_TELEA);
        filled.convertTo(in.luma, CV_32F, top / 65535.0);
    }
    return in;
}

// Ridge candidates: non-maximum suppression across the line, with a parabolic sub-pixel
// offset.  False when there are none.
bool ridge_candidates(const RidgeField& field, const cv::Mat& region, const std::vector<double>& sigmas_px,
                      cv::Mat& candidate, cv::Mat& offset) {
    bool any_candidate = false;
    for (int y = 0; y < region.rows; ++y)
        for (int x = 0; x < region.cols; ++x) {
            if (!region.at<uchar>(y, x)) continue;
            const float s = field.strength.at<float>(y, x);
            if (s <= 0) continue;
            const float nx = field.nx.at<float>(y, x), ny = field.ny.at<float>(y, x);
            const float sp = sample(field.strength, x + nx, y + ny), sm = sample(field.strength, x - nx, y - ny);
            if (!(s >= sp && s > sm)) continue;
            // A true crest is brighter (a valley darker) than both sides at its own scale; the
            // side lobes of the second derivative beside a strong line are not.
            const int si = field.scale.at<uchar>(y, x);
            const double reach = 1.5 * sigmas_px[si];
            const cv::Mat& smooth = field.smooth[si];
            const float centre = smooth.at<float>(y, x);
            const float side_a = sample(smooth, static_cast<float>(x + reach * nx), static_cast<float>(y + reach * ny));
            const float side_b = sample(smooth, static_cast<float>(x - reach * nx), static_cast<float>(y - reach * ny));
            const int sign = field.sign.at<schar>(y, x);
            if (!(sign * (centre - side_a) > 0 && sign * (centre - side_b) > 0)) continue;
            const float denom = sm - 2 * s + sp;
            offset.at<float>(y, x) = denom < 0 ? std::clamp(0.5f * (sm - sp) / denom, -0.5f, 0.5f) : 0.0f;
            candidate.at<uchar>(y, x) = 1;
            any_candidate = true;
        }
    return any_candidate;
}

// Hysteresis: grow from strong candidates through weaker ones of the same sign.
cv::Mat grow_by_hysteresis(const RidgeField& field, const cv::Mat& candidate, const cv::Mat& stored_strength,
                           const FoldDetection& out) {
    const int w = candidate.cols, h = candidate.rows;
    const auto clears = [&](int x, int y, double threshold, double floor) {
        return field.strength.at<float>(y, x) >= threshold && stored_strength.at<float>(y, x) >= floor;
    };
    cv::Mat kept = cv::Mat::zeros(candidate.size(), CV_8U);
    std::deque<cv::Point> queue;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (candidate.at<uchar>(y, x) && clears(x, y, out.high_threshold, out.high_floor)) {
                kept.at<uchar>(y, x) = 1;
                queue.emplace_back(x, y);
            }
    while (!queue.empty()) {
        const cv::Point p = queue.front();
        queue.pop_front();
        for (int k = 0; k < 8; ++k) {
            const int qx = p.x + kDx[k], qy = p.y + kDy[k];
            if (qx < 0 || qy < 0 || qx >= w || qy >= h || kept.at<uchar>(qy, qx) || !candidate.at<uchar>(qy, qx))
                continue;
            if (field.sign.at<schar>(qy, qx) != field.sign.at<schar>(p.y, p.x)) continue;
            if (!clears(qx, qy, out.low_threshold, out.low_floor)) continue;
            kept.at<uchar>(qy, qx) = 1;
            queue.emplace_back(qx, qy);
        }
    }
    return kept;
}

// Linking the kept pixels into folds: walk from line ends (one neighbour) first, then
// whatever is left (loops), preferring the neighbour that continues the current direction.
class FoldLinker {
public:
    FoldLinker(const RidgeField& field, const cv::Mat& kept, const cv::Mat& offset, const cv::Mat& unreadable,
               double min_length, FoldDetection& out)
        : field_(field),
          kept_(kept),
          offset_(offset),
          unreadable_(unreadable),
          min_length_(min_length),
          out_(out),
          w_(kept.cols),
          h_(kept.rows),
          unvisited_(kept.clone()),
          finest_(static_cast<size_t>(std::min_element(out.sigmas_px.begin(), out.sigmas_px.end()) -
                                      out.sigmas_px.begin())) {}

    void link() {
        for (int pass = 0; pass < 2; ++pass)
            for (int y = 0; y < h_; ++y)
                for (int x = 0; x < w_; ++x) {
                    if (!unvisited_.at<uchar>(y, x)) continue;
                    if (pass == 0 && neighbours(x, y, kept_).size() != 1) continue;
                    trace(cv::Point(x, y));
                }
    }

private:
    std::vector<cv::Point> neighbours(int x, int y, const cv::Mat& available) const {
        std::vector<cv::Point> n;
        for (int k = 0; k < 8; ++k) {
            const int qx = x + kDx[k], qy = y + kDy[k];
            if (qx < 0 || qy < 0 || qx >= w_ || qy >= h_ || !available.at<uchar>(qy, qx)) continue;
            if (field_.sign.at<schar>(qy, qx) != field_.sign.at<schar>(y, x)) continue;
            n.emplace_back(qx, qy);
        }
        return n;
    }

    // A point whose profile across the fold (out to 2.5x its scale, as band_centre reads it)
    // crosses a print's outline reads the inpainted fill there, not the photo: its position
    // is not a measurement, so the line is cut at it.
    bool profile_reads_print(cv::Point p, float nx, float ny) const {
        const double reach = 2.5 * out_.sigmas_px[field_.scale.at<uchar>(p.y, p.x)];
        for (double t = -reach; t <= reach; t += 0.5) {
            const int qx = std::clamp(static_cast<int>(std::lround(p.x + t * nx)), 0, w_ - 1);
            const int qy = std::clamp(static_cast<int>(std::lround(p.y + t * ny)), 0, h_ - 1);
            if (unreadable_.at<uchar>(qy, qx)) return true;
        }
        return false;
    }

    void trace(cv::Point start) {
        DetectedFold fold;
        fold.sign = field_.sign.at<schar>(start.y, start.x);
        double strength_sum = 0.0;
        auto finish_piece = [&] {
            if (!fold.points_px.empty()) {
                fold.mean_strength = strength_sum / static_cast<double>(fold.points_px.size());
                if (fold.length_px() >= min_length_) out_.folds.push_back(fold);
            }
            fold.points_px.clear();
            strength_sum = 0.0;
        };
        cv::Point p = start, dir(0, 0);
        while (true) {
            unvisited_.at<uchar>(p.y, p.x) = 0;
            const float nx = field_.nx.at<float>(p.y, p.x), ny = field_.ny.at<float>(p.y, p.x);
            if (profile_reads_print(p, nx, ny)) {
                finish_piece();
            } else {
                const float o = band_centre(field_.smooth[finest_], static_cast<float>(p.x), static_cast<float>(p.y),
                                            nx, ny, out_.sigmas_px[field_.scale.at<uchar>(p.y, p.x)], fold.sign)
                                    .value_or(offset_.at<float>(p.y, p.x));
                fold.points_px.emplace_back(p.x + o * nx, p.y + o * ny);
                strength_sum += field_.strength.at<float>(p.y, p.x);
            }
            const auto next = neighbours(p.x, p.y, unvisited_);
            if (next.empty()) break;
            const cv::Point* best = &next[0];
            double best_score = -1e9;
            for (const cv::Point& q : next) {
                const cv::Point step = q - p;
                const double len = std::hypot(step.x, step.y);
                const double score =
                    (dir.x * step.x + dir.y * step.y) / (len * std::max(1.0, std::hypot(dir.x, dir.y))) - 0.1 * len;
                if (score > best_score) {
                    best_score = score;
                    best = &q;
                }
            }
            dir = *best - p;
            p = *best;
        }
        finish_piece();
    }

    const RidgeField& field_;
    const cv::Mat& kept_;
    const cv::Mat& offset_;
    const cv::Mat& unreadable_;
    const double min_length_;
    FoldDetection& out_;
    const int w_, h_;
    cv::Mat unvisited_;
    const size_t finest_;
};

}  // namespace

FoldDetection detect_folds(const Image& photo, const Image& mask, const FoldDetectionOptions& options) {
    validate(options);
    if (mask.width != photo.width || mask.height != photo.height)
        throw InputError("fold detection: the mask is " + std::to_string(mask.width) + "x" +
                         std::to_string(mask.height) + ", the photo " + std::to_string(photo.width) + "x" +
                         std::to_string(photo.height) + "; they must be the same size");
    if (std::none_of(mask.values.begin(), mask.values.end(), [](float v) { return v > 0.5f; }))
        throw InputError("fold detection: the cloth mask is empty (no pixel above half scale); nothing to search");
    FoldDetection out;
    out.mask = mask;
    const int w = photo.width, h = photo.height;
    const double diagonal = std::hypot(w, h);
    out.sigmas_px = options.sigmas_px;
    if (out.sigmas_px.empty()) {
        const double s0 = std::max(1.5, diagonal / 600.0);
        for (int i = 0; i < 5; ++i) out.sigmas_px.push_back(s0 * std::pow(std::sqrt(2.0), i));
    }
    const double sigma_max = *std::max_element(out.sigmas_px.begin(), out.sigmas_px.end());

    // Search region: the cloth, away from its outline (the silhouette is a strong "ridge"),
    // without the prints' outlines.
    const SearchImages in = search_images(photo, mask, options, out.sigmas_px.front());
    // The ridge filter runs on the relative shading (see relative_shading); the floor of the
    // threshold is checked on the luma itself, where a photo's noise (8-bit steps, JPEG's
    // blocks) has the same size on every cloth: a fold on a dark cloth must still change the
    // stored values by more than that.
    const cv::Mat shading = relative_shading(in.luma, in.cloth);
    const RidgeField field = ridge_field(shading, out.sigmas_px, options.gamma);
    const cv::Mat stored_strength = ridge_field(in.luma, out.sigmas_px, options.gamma, RidgeParts::strength).strength;
    cv::Mat region;
    const int margin = static_cast<int>(std::ceil(2.0 * sigma_max));
    cv::erode(in.cloth, region, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * margin + 1, 2 * margin + 1)),
              cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    region &= ~in.unreadable;
    {
        cv::Mat r;
        region.convertTo(r, CV_32F, 1.0 / 255.0);
        out.search_region = detail::from_mat(r);
        in.prints.convertTo(r, CV_32F, 1.0 / 255.0);
        out.print_mask = detail::from_mat(r);
        in.unreadable.convertTo(r, CV_32F, 1.0 / 255.0);
        out.print_outline = detail::from_mat(r);
        out.shading = detail::from_mat(shading);
        out.luma = detail::from_mat(in.luma);
    }

    cv::Mat candidate = cv::Mat::zeros(in.luma.size(), CV_8U);
    cv::Mat offset = cv::Mat::zeros(in.luma.size(), CV_32F);
    if (!ridge_candidates(field, region, out.sigmas_px, candidate, offset)) return out;
    // Automatic threshold: well above the typical response of the cloth (its texture and
    // noise, measured on the relative shading), and never below a floor on the luma's own
    // response (0.006: the photo's noise floor; on s3, a dark navy shirt, the bump below its
    // deep crease responds 0.0056 and is no fold, while the studio looks' folds clear it).
    std::vector<float> region_strengths;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (region.at<uchar>(y, x)) region_strengths.push_back(field.strength.at<float>(y, x));
    const double typical_strength = median(region_strengths);
    out.high_threshold = options.high_threshold > 0 ? options.high_threshold : 4.0 * typical_strength;
    out.low_threshold = options.low_ratio * out.high_threshold;
    out.high_floor = 0.006;
    out.low_floor = options.low_ratio * out.high_floor;
    const cv::Mat kept = grow_by_hysteresis(field, candidate, stored_strength, out);
    const double min_length = options.min_length_px > 0 ? options.min_length_px : std::max(10.0, 0.03 * diagonal);
    FoldLinker(field, kept, offset, in.unreadable, min_length, out).link();
    return out;
}

Image draw_detected_folds(const Image& photo, const FoldDetection& detection) {
    cv::Mat canvas = detail::to_bgr8(photo);
    cv::Mat cloth;
    detail::to_mat(detection.mask).convertTo(cloth, CV_8U, 255.0);
    std::vector<std::vector<cv::Point>> outline;
    cv::findContours(cloth > 127, outline, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
    cv::drawContours(canvas, outline, -1, cv::Scalar(0, 230, 255), 1, cv::LINE_AA);
    for (const DetectedFold& fold : detection.folds) {
        std::vector<cv::Point> pts;
        for (const auto& p : fold.points_px) pts.emplace_back(cvRound(p.x()), cvRound(p.y()));
        const cv::Scalar colour = fold.sign > 0 ? cv::Scalar(0, 140, 255) : cv::Scalar(255, 255, 0);
        cv::polylines(canvas, pts, false, colour, 2, cv::LINE_AA);
    }
    return detail::from_bgr8(canvas);
}

}  // namespace foldcast::compare
