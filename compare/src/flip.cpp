// LDR-FLIP, written from the paper: Andersson, Nilsson, Akenine-Moller, Oskarsson, Astrom,
// Fairchild, "FLIP: A Difference Evaluator for Alternating Images", HPG 2020.
//
// Colour pipeline: sRGB -> linear RGB -> YyCxCz (opponent space, linearised CIELAB),
// contrast-sensitivity filtering per channel (sums of Gaussians, Table 1 of the paper),
// back to linear RGB clamped to [0,1] -> CIELAB -> Hunt adjustment -> HyAB distance ->
// power 0.7 -> redistribution with p_c = 0.4, p_t = 0.95 against the green-blue maximum.
// Feature pipeline: edges (1st derivative of Gaussian) and points (2nd derivative) on the
// normalised achromatic channel, w = 0.082 degrees; feature difference raised to q_f = 0.5.
// Result per pixel: colour_error ^ (1 - feature_error).  Borders are replicated.
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "foldcast/compare/diff.hpp"
#include "mat_convert.hpp"
#include "foldcast/core/colour.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::compare {
namespace {

// sRGB (D65) linear RGB <-> XYZ, the matrices of the paper's reference code.
const cv::Matx33f kRgbToXyz(0.41238656f, 0.35759149f, 0.18045049f,  //
                            0.21263682f, 0.71518298f, 0.0721802f,   //
                            0.01933062f, 0.11919716f, 0.95037259f);
const cv::Matx33f kXyzToRgb(3.24096994f, -1.53738318f, -0.49861076f,  //
                            -0.96924364f, 1.8759675f, 0.04155506f,    //
                            0.05563008f, -0.20397696f, 1.05697151f);
// Reference white: XYZ of linear RGB (1,1,1).
const cv::Vec3f kWhite(0.95042854f, 1.0f, 1.08890037f);

cv::Vec3f xyz_to_ycxcz(const cv::Vec3f& xyz) {
    const float x = xyz[0] / kWhite[0], y = xyz[1] / kWhite[1], z = xyz[2] / kWhite[2];
    return {116.0f * y - 16.0f, 500.0f * (x - y), 200.0f * (y - z)};
}

cv::Vec3f ycxcz_to_xyz(const cv::Vec3f& v) {
    const float y = (v[0] + 16.0f) / 116.0f;
    const float x = v[1] / 500.0f + y;
    const float z = y - v[2] / 200.0f;
    return {x * kWhite[0], y * kWhite[1], z * kWhite[2]};
}

cv::Vec3f xyz_to_lab(const cv::Vec3f& xyz) {
    constexpr float delta = 6.0f / 29.0f;
    auto f = [](float t) {
        return t > delta * delta * delta ? std::cbrt(t) : t / (3.0f * delta * delta) + 4.0f / 29.0f;
    };
    const float fx = f(xyz[0] / kWhite[0]), fy = f(xyz[1] / kWhite[1]), fz = f(xyz[2] / kWhite[2]);
    return {116.0f * fy - 16.0f, 500.0f * (fx - fy), 200.0f * (fy - fz)};
}

cv::Vec3f hunt(const cv::Vec3f& lab) { return {lab[0], 0.01f * lab[0] * lab[1], 0.01f * lab[0] * lab[2]}; }

float hyab(const cv::Vec3f& a, const cv::Vec3f& b) {
    return std::abs(a[0] - b[0]) + std::hypot(a[1] - b[1], a[2] - b[2]);
}

// Contrast sensitivity filter of one opponent channel: a1 sqrt(pi/b1) exp(-pi^2 r^2/b1) +
// a2 sqrt(pi/b2) exp(-pi^2 r^2/b2), r in degrees, normalised to sum 1.  All three share the
// radius set by the widest Gaussian.
cv::Mat csf_kernel(double ppd, double a1, double b1, double a2, double b2) {
    constexpr double pi = kPi;
    const double b_max = 0.04;  // largest b over the three channels (Table 1)
    const int radius = static_cast<int>(std::ceil(3.0 * std::sqrt(b_max / (2.0 * pi * pi)) * ppd));
    cv::Mat k(2 * radius + 1, 2 * radius + 1, CV_64F);
    for (int y = -radius; y <= radius; ++y)
        for (int x = -radius; x <= radius; ++x) {
            const double r2 = (x * x + y * y) / (ppd * ppd);
            k.at<double>(y + radius, x + radius) = a1 * std::sqrt(pi / b1) * std::exp(-pi * pi * r2 / b1) +
                                                   a2 * std::sqrt(pi / b2) * std::exp(-pi * pi * r2 / b2);
        }
    k /= cv::sum(k)[0];
    cv::Mat k32;
    k.convertTo(k32, CV_32F);
    return k32;
}

// Edge (first derivative) or point (second derivative) detector along x; positive weights
// normalised to sum 1 and negative weights to sum -1.
cv::Mat feature_kernel(double ppd, bool edge) {
    const double sd = 0.5 * 0.082 * ppd;
    const int radius = static_cast<int>(std::ceil(3.0 * sd));
    cv::Mat k(2 * radius + 1, 2 * radius + 1, CV_64F);
    for (int y = -radius; y <= radius; ++y)
        for (int x = -radius; x <= radius; ++x) {
            const double g = std::exp(-(x * x + y * y) / (2.0 * sd * sd));
            k.at<double>(y + radius, x + radius) = edge ? -x * g : (x * x / (sd * sd) - 1.0) * g;
        }
    double pos = 0.0, neg = 0.0;
    for (auto it = k.begin<double>(); it != k.end<double>(); ++it) (*it > 0 ? pos : neg) += *it;
    for (auto it = k.begin<double>(); it != k.end<double>(); ++it) *it = *it > 0 ? *it / pos : *it / -neg;
    cv::Mat k32;
    k.convertTo(k32, CV_32F);
    return k32;
}

cv::Mat filter(const cv::Mat& src, const cv::Mat& kernel) {
    cv::Mat dst;
    cv::filter2D(src, dst, CV_32F, kernel, cv::Point(-1, -1), 0.0, cv::BORDER_REPLICATE);
    return dst;
}

struct Prepared {
    cv::Mat lab_hunt;   // CV_32FC3, after CSF filtering
    cv::Mat edge_norm;  // CV_32F, |gradient-like response|
    cv::Mat point_norm;
};

Prepared prepare(const Image& image, double ppd) {
    cv::Mat rgb = detail::rgb_of(image);
    cv::Mat ycxcz(rgb.size(), CV_32FC3);
    for (int y = 0; y < rgb.rows; ++y)
        for (int x = 0; x < rgb.cols; ++x) {
            const cv::Vec3f c = rgb.at<cv::Vec3f>(y, x);
            const cv::Vec3f lin(srgb_to_linear(std::clamp(c[0], 0.0f, 1.0f)),
                                srgb_to_linear(std::clamp(c[1], 0.0f, 1.0f)),
                                srgb_to_linear(std::clamp(c[2], 0.0f, 1.0f)));
            ycxcz.at<cv::Vec3f>(y, x) = xyz_to_ycxcz(kRgbToXyz * lin);
        }
    std::vector<cv::Mat> ch;
    cv::split(ycxcz, ch);
    const cv::Mat filtered_a = filter(ch[0], csf_kernel(ppd, 1.0, 0.0047, 0.0, 1e-5));
    const cv::Mat filtered_rg = filter(ch[1], csf_kernel(ppd, 1.0, 0.0053, 0.0, 1e-5));
    const cv::Mat filtered_by = filter(ch[2], csf_kernel(ppd, 34.1, 0.04, 13.5, 0.025));

    Prepared p;
    p.lab_hunt.create(rgb.size(), CV_32FC3);
    for (int y = 0; y < rgb.rows; ++y)
        for (int x = 0; x < rgb.cols; ++x) {
            const cv::Vec3f v(filtered_a.at<float>(y, x), filtered_rg.at<float>(y, x), filtered_by.at<float>(y, x));
            cv::Vec3f lin = kXyzToRgb * ycxcz_to_xyz(v);
            for (int c = 0; c < 3; ++c) lin[c] = std::clamp(lin[c], 0.0f, 1.0f);
            p.lab_hunt.at<cv::Vec3f>(y, x) = hunt(xyz_to_lab(kRgbToXyz * lin));
        }

    // Achromatic channel normalised to [0,1]: (Yy + 16) / 116 = Y / Yw.
    cv::Mat achromatic = (ch[0] + 16.0f) / 116.0f;
    const cv::Mat edge_x = feature_kernel(ppd, true), point_x = feature_kernel(ppd, false);
    cv::Mat ex = filter(achromatic, edge_x), ey = filter(achromatic, edge_x.t());
    cv::Mat px = filter(achromatic, point_x), py = filter(achromatic, point_x.t());
    cv::magnitude(ex, ey, p.edge_norm);
    cv::magnitude(px, py, p.point_norm);
    return p;
}

}  // namespace

std::vector<float> flip_error_map(const Image& reference, const Image& test, double pixels_per_degree) {
    if (reference.width != test.width || reference.height != test.height)
        throw SizeMismatch("FLIP needs images of the same size");
    const Prepared r = prepare(reference, pixels_per_degree);
    const Prepared t = prepare(test, pixels_per_degree);

    constexpr float qc = 0.7f, qf = 0.5f, pc = 0.4f, pt = 0.95f;
    const cv::Vec3f green = hunt(xyz_to_lab(kRgbToXyz * cv::Vec3f(0, 1, 0)));
    const cv::Vec3f blue = hunt(xyz_to_lab(kRgbToXyz * cv::Vec3f(0, 0, 1)));
    const float cmax = std::pow(hyab(green, blue), qc);
    const float pccmax = pc * cmax;

    std::vector<float> out(static_cast<size_t>(reference.width) * reference.height);
    for (int y = 0; y < reference.height; ++y)
        for (int x = 0; x < reference.width; ++x) {
            const float de = std::pow(hyab(r.lab_hunt.at<cv::Vec3f>(y, x), t.lab_hunt.at<cv::Vec3f>(y, x)), qc);
            const float colour =
                de < pccmax ? (pt / pccmax) * de : pt + ((de - pccmax) / (cmax - pccmax)) * (1.0f - pt);
            const float feature_diff = std::max(std::abs(r.edge_norm.at<float>(y, x) - t.edge_norm.at<float>(y, x)),
                                                std::abs(r.point_norm.at<float>(y, x) - t.point_norm.at<float>(y, x)));
            const float feature = std::pow(feature_diff / std::numbers::sqrt2_v<float>, qf);
            out[static_cast<size_t>(y) * reference.width + x] = std::pow(colour, 1.0f - feature);
        }
    return out;
}

}  // namespace foldcast::compare
