#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <string>

#include "foldcast/compare/diff.hpp"
#include "mat_convert.hpp"

namespace foldcast::compare {

const char* verdict_name(DiffVerdict verdict) {
    switch (verdict) {
        case DiffVerdict::pass:
            return "PASS";
        case DiffVerdict::warning:
            return "WARNING";
        case DiffVerdict::failure:
            return "FAILURE";
        case DiffVerdict::size_mismatch:
            return "SIZE MISMATCH";
        case DiffVerdict::unreadable:
            return "UNREADABLE";
    }
    return "?";
}

namespace {

Image colour_mapped(const std::vector<float>& values, int width, int height, float full_scale) {
    cv::Mat grey(height, width, CV_8U);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const float v = full_scale > 0 ? values[static_cast<size_t>(y) * width + x] / full_scale : 0.0f;
            grey.at<uchar>(y, x) = cv::saturate_cast<uchar>(std::clamp(v, 0.0f, 1.0f) * 255.0f);
        }
    cv::Mat bgr;
    cv::applyColorMap(grey, bgr, cv::COLORMAP_MAGMA);
    return detail::from_bgr8(bgr);
}

}  // namespace

void validate(const DiffThresholds& th) {
    auto check = [](double v, const char* flag, bool percent) {
        if (std::isnan(v) || v < 0.0 || (percent && v > 100.0))
            throw InputError(std::string(flag) + " " + std::to_string(v) + ": must be " +
                             (percent ? "a percentage in [0, 100]" : "a number >= 0 (inf allowed)"));
    };
    check(th.fail, "--fail", false);
    check(th.fail_percent, "--failpercent", true);
    check(th.hard_fail, "--hardfail", false);
    check(th.warn, "--warn", false);
    check(th.warn_percent, "--warnpercent", true);
    check(th.hard_warn, "--hardwarn", false);
    if (th.allow_failures < 0)
        throw InputError("--allowfailures " + std::to_string(th.allow_failures) + ": must be a whole number >= 0");
}

DiffReport diff_images(const Image& reference, const Image& test, const DiffThresholds& th, Image* heat_map,
                       HeatMapKind kind) {
    validate(th);
    if (reference.width != test.width || reference.height != test.height || reference.channels != test.channels)
        throw SizeMismatch("images differ in size: " + std::to_string(reference.width) + "x" +
                           std::to_string(reference.height) + "x" + std::to_string(reference.channels) + " vs " +
                           std::to_string(test.width) + "x" + std::to_string(test.height) + "x" +
                           std::to_string(test.channels) + " (width x height x channels)");
    DiffReport r;
    r.width = reference.width;
    r.height = reference.height;
    r.channels = reference.channels;
    const long long pixels = static_cast<long long>(r.width) * r.height;
    const int nc = r.channels;
    std::vector<float> pixel_max(static_cast<size_t>(pixels), 0.0f);
    double sum_abs = 0.0, sum_sq = 0.0;
    for (long long i = 0; i < pixels; ++i) {
        bool warned = false, failed = false;
        float worst = 0.0f;
        for (int c = 0; c < nc; ++c) {
            const size_t k = static_cast<size_t>(i) * nc + c;
            // Fail closed: a NaN on either side (or inf - inf) is an infinite difference, never
            // one that every comparison with a threshold lets through.
            double d = std::abs(static_cast<double>(reference.values[k]) - test.values[k]);
            if (std::isnan(d)) {
                d = std::numeric_limits<double>::infinity();
                ++r.nan_values;
            }
            sum_abs += d;
            sum_sq += d * d;
            worst = std::max(worst, static_cast<float>(d));
            if (d > r.max_abs_error) {
                r.max_abs_error = d;
                r.max_x = static_cast<int>(i % r.width);
                r.max_y = static_cast<int>(i / r.width);
                r.max_channel = c;
            }
            warned = warned || d > th.warn;
            failed = failed || d > th.fail;
        }
        pixel_max[static_cast<size_t>(i)] = worst;
        r.warn_pixels += warned;
        r.fail_pixels += failed;
    }
    const double values = static_cast<double>(std::max<long long>(pixels * nc, 1));
    r.mean_abs_error = sum_abs / values;
    r.rms_error = std::sqrt(sum_sq / values);
    r.psnr_db = r.rms_error > 0 ? 20.0 * std::log10(1.0 / r.rms_error) : std::numeric_limits<double>::infinity();
    const double npels = static_cast<double>(std::max<long long>(pixels, 1));
    r.warn_percent = 100.0 * r.warn_pixels / npels;
    r.fail_percent = 100.0 * r.fail_pixels / npels;

    // idiff's decision, including its strict comparisons and its first rule; NaN first.
    if (r.nan_values > 0)
        r.verdict = DiffVerdict::failure;
    else if (r.fail_pixels <= th.allow_failures)
        r.verdict = DiffVerdict::pass;
    else if (r.fail_pixels > th.fail_percent / 100.0 * npels || r.max_abs_error > th.hard_fail)
        r.verdict = DiffVerdict::failure;
    else if (r.warn_pixels > th.warn_percent / 100.0 * npels || r.max_abs_error > th.hard_warn)
        r.verdict = DiffVerdict::warning;
    else
        r.verdict = DiffVerdict::pass;

    if (pixels > 0) {
        r.ssim = ssim_luma(reference, test);
        const std::vector<float> flip = flip_error_map(reference, test);
        double flip_sum = 0.0;
        for (float f : flip) {
            flip_sum += f;
            r.flip_max = std::max(r.flip_max, static_cast<double>(f));
        }
        r.flip_mean = flip_sum / npels;
        if (heat_map) {
            *heat_map = kind == HeatMapKind::flip
                            ? colour_mapped(flip, r.width, r.height, 1.0f)
                            : colour_mapped(pixel_max, r.width, r.height, static_cast<float>(r.max_abs_error));
        }
    }
    return r;
}

}  // namespace foldcast::compare
