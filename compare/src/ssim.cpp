// Mean SSIM, Wang, Bovik, Sheikh, Simoncelli, "Image quality assessment: from error
// visibility to structural similarity", IEEE TIP 2004: Gaussian window 11x11 sigma 1.5,
// K1 = 0.01, K2 = 0.03, dynamic range L = 1.
#include <opencv2/imgproc.hpp>

#include "foldcast/compare/diff.hpp"
#include "mat_convert.hpp"

namespace foldcast::compare {

double ssim_luma(const Image& reference, const Image& test) {
    if (reference.width != test.width || reference.height != test.height)
        throw SizeMismatch("SSIM needs images of the same size");
    cv::Mat a, b;
    detail::luma_of(reference).convertTo(a, CV_64F);
    detail::luma_of(test).convertTo(b, CV_64F);
    constexpr double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
    const cv::Size window(11, 11);
    auto blur = [&](const cv::Mat& m) {
        cv::Mat out;
        cv::GaussianBlur(m, out, window, 1.5, 1.5, cv::BORDER_REFLECT);
        return out;
    };
    const cv::Mat mu_a = blur(a), mu_b = blur(b);
    const cv::Mat var_a = blur(a.mul(a)) - mu_a.mul(mu_a);
    const cv::Mat var_b = blur(b.mul(b)) - mu_b.mul(mu_b);
    const cv::Mat cov = blur(a.mul(b)) - mu_a.mul(mu_b);
    cv::Mat num = (2.0 * mu_a.mul(mu_b) + c1).mul(2.0 * cov + c2);
    cv::Mat den = (mu_a.mul(mu_a) + mu_b.mul(mu_b) + c1).mul(var_a + var_b + c2);
    cv::Mat map;
    cv::divide(num, den, map);
    // "valid" positions: the window lies wholly inside the image (Wang's reference code).
    constexpr int half = 5;
    if (map.cols > 2 * half && map.rows > 2 * half)
        map = map(cv::Rect(half, half, map.cols - 2 * half, map.rows - 2 * half));
    return cv::mean(map)[0];
}

}  // namespace foldcast::compare
