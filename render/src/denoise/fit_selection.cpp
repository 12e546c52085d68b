#include "fit_selection.hpp"

#include <opencv2/imgproc.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "foldcast/core/colour.hpp"

namespace foldcast::render {
namespace {

// The windows the fits of alpha sum over (Gaussian sigma, pixels at 320x180, in proportion to
// the image's size above it): a fold's width on the cloth; on the smooth backdrop, whose
// residual error is blotches a few pixels across, wider.  At 320x180 a backdrop window of 16
// was no better (22.73 against 22.76); the README's 1280x720 render against plain 256 spp
// (RMSE) with the windows at 2 and 8 pixels 0.004805, at 8 and 32 (these) 0.004738, against
// 0.004772 before this stage.
constexpr float kClothWindowPx = 2.0f;
constexpr float kBackdropWindowPx = 8.0f;
constexpr float kWindowImagePixels = 320.0f * 180.0f;
// alpha may go half a step beyond the first setting, away from the second: a sharper fit
// than either (320x180, seeds 1-3: [0, 1] 23.38, [-0.5, 1] 23.30, [-1, 1] 23.32, [-0.5, 1.5]
// 23.41 before the backdrop's blend).
constexpr float kMinBlendAlpha = -0.5f, kMaxBlendAlpha = 1.0f;
// The cloth's averaged fits (cloth_light_fit.hpp) blended with each pixel's own fit by the
// halves as the settings are, over the same window: the averaging lowers the noise of the
// flat cloth and biases a glossy sheen lobe, which a neighbour's fit extrapolated to the pixel
// misses.  The share of the own fit may go up to a step beyond it, away from the averaged:
// sharper than either.  The default scene in each look, seeds 1-3 (before the averaging backed off by
// agreement), upper bound 1 / 1.5 / 2 / 3: silk charmeuse 53.53 / 52.94 / 52.77 / 52.69, the
// default scene 18.13 / 18.12 / 18.12 / 18.12; the window at 1 / 3 pixels with the bound 2:
// silk 52.10 / 53.17, the default scene 18.20 / 18.10 (docs/benchmarks.md, "Glossy looks: the
// averaging backs off").
constexpr float kMaxOwnShare = 2.0f;

// `values` summed over a box of (2 radius + 1)^2 pixels about each pixel, from the image's
// integral (the cost does not grow with the box; in double, so that the differences of large
// sums keep the small ones' digits).
std::vector<float> box_sum(const std::vector<float>& values, int w, int h, int radius) {
    const std::size_t stride = std::size_t(w) + 1;
    cv::Mat_<double> integral;
    cv::integral(cv::Mat_<float>(h, w, const_cast<float*>(values.data())), integral, CV_64F);
    const double* const prefix = integral[0];
    std::vector<float> out(values.size());
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y) {
            const std::size_t top = std::size_t(std::max(0, y - radius)) * stride;
            const std::size_t bottom = std::size_t(std::min(h, y + radius + 1)) * stride;
            for (int x = 0; x < w; ++x) {
                const std::size_t left = std::size_t(std::max(0, x - radius));
                const std::size_t right = std::size_t(std::min(w, x + radius + 1));
                out[std::size_t(y) * w + x] =
                    float(prefix[bottom + right] - prefix[bottom + left] - prefix[top + right] + prefix[top + left]);
            }
        }
    });
    return out;
}

// `values` of the masked pixels summed over each pixel's window: three boxes of radius about
// `sigma_px` in turn, close to a Gaussian of that sigma (a single box of the same variance was
// worse at 320x180: 22.92, three 22.81, the Gaussian 22.76), at a cost that does not grow with
// it.  Only ratios of two such sums are used, so they are not normalised.
std::vector<float> window_sum(const std::vector<float>& values, const std::vector<std::int32_t>& mask, int w, int h,
                              float sigma_px) {
    const int radius = std::max(1, int(std::lround(sigma_px)));
    std::vector<float> sum(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) sum[i] = mask[i] ? values[i] : 0.0f;
    for (int k = 0; k < 3; ++k) sum = box_sum(sum, w, h, radius);
    return sum;
}

// A regression run on each buffer under one setting.
struct Candidate {
    std::vector<V3> whole, from_a, from_b;
};

// What `regress` (the cloth's or the backdrop's regression, given the light to fit, its
// noise and the guide's luminance) makes of buffer `buffer` fitting `share` of its noisy light.
template <class Regress>
std::vector<V3> run(const FilteredBuffer& buffer, float share, Regress&& regress) {
    const std::size_t count = buffer.noisy->size();
    std::vector<V3> fitted(count), out = *buffer.filtered;
    std::vector<float> guide(count), fitted_noise(count);
    for (std::size_t i = 0; i < count; ++i) {
        fitted[i] = share * (*buffer.noisy)[i] + (1.0f - share) * (*buffer.filtered)[i];
        guide[i] = luminance((*buffer.filtered)[i]);
        fitted_noise[i] = share * share * (*buffer.noise)[i];
    }
    regress(fitted, fitted_noise, guide, *buffer.variance, out);
    return out;
}

template <class Regress>
Candidate candidate(const SelectionInput& in, float share, Regress&& regress) {
    return {run(in.whole, share, regress), run(in.half_a, share, regress), run(in.half_b, share, regress)};
}

// alpha per masked pixel: the least-squares fit over its window of f0 + alpha (f1 - f0) on
// either half to the other half's noisy light, clamped to [lo, hi].
std::vector<float> fit_alpha(const SelectionInput& in, const std::vector<std::int32_t>& mask, const Candidate& f0,
                             const Candidate& f1, float window_px, float lo, float hi) {
    const std::size_t count = mask.size();
    const std::vector<V3>& a = *in.half_a.noisy;
    const std::vector<V3>& b = *in.half_b.noisy;
    const std::vector<V3>& weight = *in.error_weight;
    std::vector<float> num(count, 0.0f), den(count, 0.0f);
    for (std::size_t i = 0; i < count; ++i) {
        if (!mask[i]) continue;
        const V3 da = f1.from_a[i] - f0.from_a[i], db = f1.from_b[i] - f0.from_b[i];
        const V3 ra = b[i] - f0.from_a[i], rb = a[i] - f0.from_b[i];
        num[i] = weight[i].dot(da.cwiseProduct(ra) + db.cwiseProduct(rb));
        den[i] = weight[i].dot(da.cwiseProduct(da) + db.cwiseProduct(db));
    }
    const int w = in.cloth.width, h = in.cloth.height;
    const std::vector<float> sum_num = window_sum(num, mask, w, h, window_px), sum_den = window_sum(den, mask, w, h, window_px);
    std::vector<float> alpha(count, 0.0f);
    for (std::size_t i = 0; i < count; ++i)
        if (mask[i] && sum_den[i] > 0.0f) alpha[i] = std::clamp(sum_num[i] / sum_den[i], lo, hi);
    return alpha;
}

// f0 + alpha (f1 - f0) on the masked pixels of each buffer (f0's elsewhere).
Candidate mix(const std::vector<std::int32_t>& mask, const Candidate& f0, const Candidate& f1,
              const std::vector<float>& alpha) {
    Candidate out = f0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (!mask[i]) continue;
        out.whole[i] += alpha[i] * (f1.whole[i] - f0.whole[i]);
        out.from_a[i] += alpha[i] * (f1.from_a[i] - f0.from_a[i]);
        out.from_b[i] += alpha[i] * (f1.from_b[i] - f0.from_b[i]);
    }
    return out;
}

// out = f0 + alpha (f1 - f0) on the masked pixels, alpha from fit_alpha.
void blend(const SelectionInput& in, const std::vector<std::int32_t>& mask, const Candidate& f0, const Candidate& f1,
           float window_px, float lo, float hi, std::vector<V3>& out) {
    const std::vector<float> alpha = fit_alpha(in, mask, f0, f1, window_px, lo, hi);
    for (std::size_t i = 0; i < mask.size(); ++i)
        if (mask[i]) out[i] = f0.whole[i] + alpha[i] * (f1.whole[i] - f0.whole[i]);
}

}  // namespace

void regress_still_by_halves(const SelectionInput& in, std::vector<V3>& out) {
    const auto cloth = [&](const RegressionSetting& s, std::vector<V3>* own_fits) {
        return [&in, s, own_fits](const std::vector<V3>& light, const std::vector<float>& noise,
                                  const std::vector<float>& guide, const std::vector<float>& variance,
                                  std::vector<V3>& result) {
            ClothRegressionInput c = in.cloth;
            c.light = &light, c.fitted_variance = &noise, c.guide = &guide, c.variance = &variance;
            c.own_fits = own_fits;
            c.spatial_sigma *= s.sigma_scale;
            regress_cloth(c, result);
        };
    };
    const auto backdrop = [&](const std::vector<V3>& light, const std::vector<float>&, const std::vector<float>& guide,
                              const std::vector<float>& variance, std::vector<V3>& result) {
        BackdropRegressionInput b = in.backdrop;
        b.light = &light, b.guide = &guide, b.variance = &variance;
        regress_backdrop(b, result);
    };
    const float scale = std::max(1.0f, std::sqrt(float(out.size()) / kWindowImagePixels));
    // One regression's candidates at a time (the cloth's, averaged and own, twelve images with
    // their two blends; then the backdrop's six).  Each regression reads and writes its own
    // pixels only, so the backdrop's candidates do not see the cloth's blend, though they
    // start from `out`.
    {
        // Each cloth setting's averaged fits and, from the same regression, each pixel's own fit.
        const std::vector<std::int32_t>& mask = *in.cloth.cloth;
        const auto both = [&](const RegressionSetting& s, Candidate& averaged, Candidate& own) {
            const auto one = [&](const FilteredBuffer& buffer, std::vector<V3>& mean, std::vector<V3>& own_fit) {
                own_fit = *buffer.filtered;
                mean = run(buffer, s.noisy_share, cloth(s, &own_fit));
            };
            one(in.whole, averaged.whole, own.whole);
            one(in.half_a, averaged.from_a, own.from_a);
            one(in.half_b, averaged.from_b, own.from_b);
        };
        Candidate averaged0, own0, averaged1, own1;
        both(kClothSettings[0], averaged0, own0);
        both(kClothSettings[1], averaged1, own1);
        // The settings' blend chosen on the averaged fits, then the same blend of the own fits,
        // and between the two a second blend by the halves (kMaxOwnShare).
        const std::vector<float> alpha =
            fit_alpha(in, mask, averaged0, averaged1, scale * kClothWindowPx, kMinBlendAlpha, kMaxBlendAlpha);
        const Candidate averaged = mix(mask, averaged0, averaged1, alpha), own = mix(mask, own0, own1, alpha);
        blend(in, mask, averaged, own, scale * kClothWindowPx, 0.0f, kMaxOwnShare, out);
    }
    const Candidate f0 = candidate(in, kBackdropSettings[0].noisy_share, backdrop);
    const Candidate f1 = candidate(in, kBackdropSettings[1].noisy_share, backdrop);
    blend(in, *in.backdrop.backdrop, f0, f1, scale * kBackdropWindowPx, kMinBlendAlpha, kMaxBlendAlpha, out);
}

}  // namespace foldcast::render
