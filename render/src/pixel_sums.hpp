#pragma once
// What one pixel has gathered (radiance, luminance moments, the first hit's features for the
// AOVs and the denoiser) and the adaptive-sampling decision the tracer takes per 4x4 packet
// of pixels from those sums.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "foldcast/core/colour.hpp"
#include "path_integrator.hpp"
#include "shading.hpp"

namespace foldcast::render {

// Adaptive sampling decides for a whole 4x4 packet at powers of two from this many samples
// on: there the Sobol' points of each pixel are a complete stratification, and so are the
// first half of them, so the difference between the pixel's mean over all its samples and
// over the first half is an estimate of the error of the stratified mean (the sample
// variance is not: it counts the variance that stratification removes, such as which light
// a sample picks, and over-states the error).  One pixel's difference is a
// one-sample estimate; the packet's 16 together are a fair one, and 16 pixels x 4 samples
// rarely all miss a bright path that one of them would have found.
constexpr int kMinAdaptiveSpp = 4;

// Display units (sRGB, 0-1) per unit of linear radiance at `linear`: the slope of the
// transfer curve, so noise is judged as it will be seen.
inline float srgb_slope(float linear) {
    if (linear <= 0.0031308f) return 12.92f;
    return 1.055f / 2.4f * std::pow(linear, 1.0f / 2.4f - 1.0f);
}

// What one pixel has gathered so far.
struct PixelSums {
    V3 all = V3::Zero(), fg = V3::Zero();
    int fg_count = 0, garment_count = 0, turning_count = 0, n = 0;
    double lum = 0.0, lum2 = 0.0;  // luminance sums for the variance
    V3 albedo = V3::Zero(), normal = V3::Zero(), shading_normal = V3::Zero();
    float depth = 0.0f, fold = 0.0f;
    bool done = false;
    // The colour sums at the last two powers of two of n: the denoiser's two half buffers
    // (the first half of a pixel's samples and the rest, each a complete Sobol' stratification
    // when n is a power of two).
    struct Snapshot {
        V3 all = V3::Zero(), fg = V3::Zero();
        int fg_count = 0, n = 0;
    };
    Snapshot last_pow2, prev_pow2;

    void add(const PathSample& s) {
        ++n;
        all += s.radiance;
        garment_count += s.garment ? 1 : 0;
        turning_count += s.turning ? 1 : 0;
        if (s.foreground) {
            fg += s.radiance;
            ++fg_count;
        }
        const double l = luminance(s.radiance);
        lum += l;
        lum2 += l * l;
        albedo += s.albedo;
        normal += V3(s.normal.x(), s.normal.y(), s.normal.z());
        shading_normal += V3(s.shading_normal.x(), s.shading_normal.y(), s.shading_normal.z());
        depth += s.depth;
        fold += s.fold;
        if ((n & (n - 1)) == 0) {
            prev_pow2 = last_pow2;
            last_pow2 = Snapshot{all, fg, fg_count, n};
        }
    }
    // The samples of the first half buffer: n / 2 when n is a power of two, otherwise the
    // largest power of two below n (0 when n < 2: no halves).
    const Snapshot& first_half() const { return last_pow2.n == n ? prev_pow2 : last_pow2; }
    float variance_of_mean() const {
        if (n < 2) return 0.0f;
        const double mean = lum / n;
        return static_cast<float>(std::max(0.0, (lum2 - lum * mean) / (n - 1)) / n);
    }
    // The error of the mean in display units, from its difference to the mean of the first
    // half of the samples (the last power-of-two checkpoint); infinite where n is not twice it.
    double lum_checkpoint = 0.0;
    int n_checkpoint = 0;
    float half_difference_display(float gain) const {
        if (n_checkpoint == 0 || 2 * n_checkpoint != n) return std::numeric_limits<float>::infinity();
        const double mean = lum / n, half = lum_checkpoint / n_checkpoint;
        return static_cast<float>(std::abs(mean - half)) * gain * srgb_slope(static_cast<float>(mean) * gain);
    }
    void checkpoint() { lum_checkpoint = lum, n_checkpoint = n; }
};

// Whether the denoiser will average the packet's pixels together: their first hits agree
// in shading normal, depth and albedo (its edge-stopping features), as on the flat backdrop.
inline bool packet_is_smooth(const std::array<PixelSums, 16>& sums, const std::array<bool, 16>& inside) {
    V3 normal = V3::Zero(), albedo = V3::Zero();
    double depth = 0.0;
    int count = 0;
    for (int k = 0; k < 16; ++k)
        if (inside[k]) {
            const PixelSums& p = sums[k];
            normal += p.shading_normal.normalized();
            albedo += p.albedo / static_cast<float>(p.n);
            depth += p.depth / p.n;
            ++count;
        }
    if (count == 0 || normal.squaredNorm() == 0.0f) return false;
    normal.normalize(), albedo /= static_cast<float>(count), depth /= count;
    for (int k = 0; k < 16; ++k)
        if (inside[k]) {
            const PixelSums& p = sums[k];
            if (p.shading_normal.normalized().dot(normal) < 0.98f) return false;
            if (std::abs(p.depth / p.n - depth) > 0.02 * depth) return false;
            if ((p.albedo / static_cast<float>(p.n) - albedo).cwiseAbs().maxCoeff() > 0.05f) return false;
        }
    return true;
}

// A packet is done when the RMS of its pixels' estimated errors is below the threshold and
// none is above four times it (a lone bright path keeps the packet going).  When the image
// will be denoised and the packet is smooth, the error that will be seen is that of the
// packet's mean, which the denoiser's averaging leaves: the errors count 1/sqrt(pixels).
inline bool packet_error_below(const std::array<PixelSums, 16>& sums, const std::array<bool, 16>& inside, float gain,
                               float threshold, bool denoise) {
    double sum_squares = 0.0, largest = 0.0;
    int count = 0;
    for (int k = 0; k < 16; ++k) {
        if (!inside[k]) continue;
        const double e = sums[k].half_difference_display(gain);
        if (!std::isfinite(e)) return false;
        sum_squares += e * e, largest = std::max(largest, e);
        ++count;
    }
    if (count == 0) return false;
    double rms = std::sqrt(sum_squares / count);
    if (denoise && packet_is_smooth(sums, inside)) {
        const double averaged = std::sqrt(static_cast<double>(count));
        rms /= averaged, largest /= averaged;
    }
    return rms < threshold && largest < 4.0 * threshold;
}

}  // namespace foldcast::render
