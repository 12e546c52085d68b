#pragma once
// Image diff for visual regression, with the conventions of OpenImageIO's idiff (checked
// against idiff 2.4.7): a pixel fails when any channel differs by more than `fail` (values
// in [0,1]) and warns when any differs by more than `warn`.  Verdict, in idiff's order:
//   1. at most allow_failures pixels fail (default 0)                     -> PASS
//   2. more than fail_percent % fail, or the largest difference > hard_fail -> FAILURE
//   3. more than warn_percent % warn, or the largest difference > hard_warn -> WARNING
//   4. otherwise                                                         -> PASS
// Rule 1 is idiff's: with no failing pixel, warnings and the hard limits do not matter.
// Before all of them, ours: a NaN in either image is a FAILURE (a gate fails closed).
#include <limits>

#include "foldcast/compare/image.hpp"

namespace foldcast::compare {

struct DiffThresholds {
    double fail = 1e-6;
    double fail_percent = 0.0;
    double hard_fail = std::numeric_limits<double>::infinity();
    double warn = 1e-6;
    double warn_percent = 0.0;
    double hard_warn = std::numeric_limits<double>::infinity();
    long long allow_failures = 0;
};

// Exit statuses of `foldcast diff` (idiff's): 0 pass, 1 warning, 2 failure, 3 size
// mismatch, 4 unreadable file.
enum class DiffVerdict { pass = 0, warning = 1, failure = 2, size_mismatch = 3, unreadable = 4 };
const char* verdict_name(DiffVerdict verdict);  // "PASS", "WARNING", ...

// The two images differ in width, height or channel count.
class SizeMismatch : public InputError {
public:
    using InputError::InputError;
};

struct DiffReport {
    int width = 0, height = 0, channels = 0;
    double mean_abs_error = 0.0;  // over all pixels and channels
    double max_abs_error = 0.0;
    int max_x = 0, max_y = 0, max_channel = 0;  // where max_abs_error occurs (first in scan order)
    double rms_error = 0.0;
    double psnr_db = 0.0;    // 20 log10(1 / rms); +inf for identical images
    double ssim = 1.0;       // mean SSIM of the Rec.709 luma (Gaussian 11x11, sigma 1.5)
    double flip_mean = 0.0;  // mean LDR-FLIP error in [0,1] (RGB, alpha ignored)
    double flip_max = 0.0;
    long long warn_pixels = 0;
    long long fail_pixels = 0;
    long long nan_values = 0;   // channels where either image holds NaN: always FAILURE
    double warn_percent = 0.0;  // 100 * warn_pixels / pixels
    double fail_percent = 0.0;
    DiffVerdict verdict = DiffVerdict::pass;
};

enum class HeatMapKind {
    flip,       // per-pixel FLIP error through the magma colour map (0 black .. 1 white-yellow)
    abs_error,  // max over channels of |A-B|, scaled so that the largest error is full scale
};

// Throws InputError naming the flag when a threshold is NaN or negative, or a percentage is
// over 100.
void validate(const DiffThresholds& thresholds);

// Compares `test` against `reference` (validating the thresholds first).  A channel where
// either image holds NaN counts as an infinite difference, so it fails at any threshold.  Throws SizeMismatch when
// sizes or channel counts differ.  When `heat_map` is given it receives an RGB picture of the differences.
DiffReport diff_images(const Image& reference, const Image& test, const DiffThresholds& thresholds,
                       Image* heat_map = nullptr, HeatMapKind kind = HeatMapKind::flip);

// The parts, exposed for tests and other callers.
// Mean SSIM (Wang et al. 2004) of two single-channel images with values in [0,1]
// (K1 = 0.01, K2 = 0.03, data range 1), Gaussian window 11x11 sigma 1.5, averaged over the
// positions where the window lies inside the image ("valid"); images smaller than the
// window are averaged over every pixel with reflected borders.
double ssim_luma(const Image& reference, const Image& test);

// Per-pixel LDR-FLIP (Andersson et al. 2020, "FLIP: A Difference Evaluator for Alternating
// Images") of two sRGB-encoded images in [0,1]; `pixels_per_degree` = 67 is the paper's
// default viewing condition (0.7 m from a 0.7 m wide 4K monitor).  Row-major, width*height.
std::vector<float> flip_error_map(const Image& reference, const Image& test, double pixels_per_degree = 67.0);

}  // namespace foldcast::compare
