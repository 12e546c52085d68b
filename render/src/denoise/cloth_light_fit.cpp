#include "cloth_light_fit.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>

#include "foldcast/core/colour.hpp"
#include "foldcast/core/fast_math.hpp"
#include "tap_weights.hpp"

namespace foldcast::render {
namespace {

// A 9 x 9 window with Gaussian spatial weights (ClothRegressionInput::spatial_sigma);
// regressors 1, the normal's change (3), the offset (2) and, for stills, the depth's change
// (1) and the offset's squares and product (3).  The settings were chosen on the default
// scene at 640x360 and 16 spp (docs/benchmarks.md, "Cloth regression": 11 x 11 was 1 % better
// and 50 % dearer).
constexpr int kClothRadius = 4;
constexpr int kTaps = 2 * kClothRadius + 1;
constexpr int kFrameRegressors = 6;
// Stills add the depth's change and the offset's squares and product (a crease's trough is a
// minimum of the light across the fold: a plane fitted over it comes out too bright at the
// bottom and too dark on the shoulders).  Default scene, 16 spp + denoise, seeds 1-3: 18.39
// without the quadratic terms, 18.34 with (dx^2 + dy^2) alone, 18.15 with all three; 640x360
// 10.21 / 10.20 (docs/benchmarks.md, "The cloth's fit, quadratic in the offset").
constexpr int kStillRegressors = 10;
// The upper triangle of X^T W X for n regressors.
constexpr int products(int n) { return n * (n + 1) / 2; }
// A tap's depth may differ from the pixel's by this share of the depth per pixel of distance
// (exp(-1) there): the same sheet of cloth, not a fold behind it.  With the depth's change a
// regressor (stills) the model itself follows the light along a fold turning away from the
// camera and across the mixed pixels of a self-occlusion edge (front and back in proportion
// to their mean depth), so more of the depth is let in.  Default scene, 16 spp + denoise,
// squared error (seeds 1-3) with the still's window (still_spatial_sigma) at 0.003 / 0.005 /
// 0.01: 24.3 / 24.0 / 24.0 at 320x180, - / 12.55 / 12.50 at 640x360; the twill close-up's SSIM
// 0.998190 at 0.002, 0.998197 at 0.005, 0.998198 at 0.01 as without the regressor
// (docs/benchmarks.md, 2026-11-27).
constexpr float kFrameDepthTolerance = 0.002f;
constexpr float kStillDepthTolerance = 0.01f;
// The depth regressor's unit, a share of the pixel's depth: the ridge below is on the scale of
// a unit slope.
constexpr float kDepthRegressorUnit = 0.01f;
constexpr double kClothRidge = 1e-3;  // on the slopes, so that a flat patch still has a fit
// A fit whose residual variance is beyond this many times the light's noise does not follow
// the light (a glossy weave's highlight is not linear in the normal): the pixel keeps the
// passes' result.  8 / 16 / 32 / none: satin 0.0078 / 0.0078 / 0.0079 / 0.0083, silk
// charmeuse 0.0077 / 0.0079 / 0.0082 / 0.0093, the default scene 14.7 / 14.5 / 14.6 / 14.6
// (docs/benchmarks.md, "Every look, measured").
constexpr double kClothMisfit = 16.0;
// The fits averaged at a pixel (average_fits): those about it and its neighbours within this
// many pixels on either axis.  Default scene, 16 spp + denoise, seeds 1-3, squared error at
// 320x180 / 640x360 with 1: 18.89 / 10.28, 2: 18.85 / 10.30, 4 (the whole window, three times
// the cost): 18.85 / 10.35 (docs/benchmarks.md, "The cloth's fits averaged").
constexpr int kAverageRadius = 2;
// A neighbour's fit whose luminance at the pixel differs from the pixel's own fit's by d
// weighs exp(-d^2 / (this x the fitted light's noise variance)) of its tap weight: on glossy
// cloth a sheen lobe turns faster than a fit linear (or quadratic) in the normal follows, a
// neighbour's fit extrapolated to the pixel is biased there, and the mean backs off to the
// pixel's own.  The default scene in each look, seeds 1-3, silk charmeuse with the own fits' blend
// (fit_selection.cpp): 52.77 without, 52.38 / 52.19 at 3 / 1; the default scene 18.12
// / 18.13 / 18.13; alone (without that blend) 0.1 / 0.3 / 1: silk 52.99 / 53.40 / 54.27, the
// default scene 18.17 / 18.13 / 18.11 (docs/benchmarks.md, "Glossy looks: the averaging backs off").
constexpr float kAgreement = 1.0f;

// What a tap at offset (dx, dy) brings whatever the pixel: its spatial weight, 1 / its
// distance, and its offset regressors (and their squares).
struct Offsets {
    float spatial[kTaps][kTaps], inv_distance[kTaps][kTaps], regressor[kTaps], square[kTaps];
    explicit Offsets(float sigma) {
        float g[kTaps];
        for (int d = 0; d < kTaps; ++d) {
            const float o = float(d - kClothRadius);
            g[d] = std::exp(-o * o / (2.0f * sigma * sigma));
            regressor[d] = o / kClothRadius;
            square[d] = regressor[d] * regressor[d];
        }
        for (int a = 0; a < kTaps; ++a)
            for (int b = 0; b < kTaps; ++b) {
                const float dx = float(b - kClothRadius), dy = float(a - kClothRadius);
                spatial[a][b] = g[a] * g[b];
                inv_distance[a][b] = 1.0f / std::max(1.0f, std::sqrt(dx * dx + dy * dy));
            }
    }
};

// The image's arrays, the light split by channel so that four pixels' are contiguous.
struct Planes {
    int w = 0, h = 0;
    float depth_tolerance = kFrameDepthTolerance;
    const float *guide, *variance, *fitted_variance, *nx, *ny, *nz, *depth, *ax, *ay, *az;
    const std::int32_t* cloth;
    std::vector<float> red, green, blue;
    // Each cloth pixel's fitted coefficients (kStillRegressors x 3, regressor-major), the first
    // NaN where its fit failed or did not fit; other pixels' are not written (nor their memory
    // touched).  Null when the fits are not averaged (average_fits).
    float* betas = nullptr;
};

constexpr int kBetaFloats = kStillRegressors * 3;

// What the weights and regressors of a fit about pixel i take from the pixel itself.
struct Centre {
    float inv_tolerance, scale_floor, inv_depth_unit;
};
inline Centre centre(const Planes& p, std::size_t i) {
    const float relative = kColourRelative * p.guide[i];
    return {1.0f / (p.depth_tolerance * p.depth[i] + 1e-6f), relative * relative + 1e-8f,
            1.0f / (kDepthRegressorUnit * p.depth[i] + 1e-6f)};
}

// The exponent of tap j's weight in the fit about pixel i (c: centre(p, i)), apart from the
// spatial weight: the depth's difference beyond the tolerance per pixel of distance, and the
// colour weight.
inline float tap_exponent(const Planes& p, const Centre& c, std::size_t i, std::size_t j, float inv_distance) {
    const float difference = p.guide[j] - p.guide[i];
    const float colour =
        difference * difference / (kColourSigma * kColourSigma * (p.variance[i] + p.variance[j]) + c.scale_floor);
    return std::abs(p.depth[j] - p.depth[i]) * c.inv_tolerance * inv_distance + colour;
}

// Whether tap j may enter pixel i's fit: cloth of about the same albedo.
inline bool alike(const Planes& p, std::size_t i, std::size_t j) {
    return p.cloth[j] && std::abs(p.ax[j] - p.ax[i]) < kRegressionSameAlbedo &&
           std::abs(p.ay[j] - p.ay[i]) < kRegressionSameAlbedo && std::abs(p.az[j] - p.az[i]) < kRegressionSameAlbedo;
}

// Tap j of the fit about pixel i (c: centre(p, i)), at (dx, dy) from i: its weight (the
// spatial one times the depth and colour weights) and its regressors.  The fit and the
// averaging of fits (average_fits) both take their taps from here.
struct Tap {
    float weight;
    float r[kStillRegressors];
};
inline Tap tap(const Planes& p, const Offsets& o, const Centre& c, std::size_t i, std::size_t j, int dx, int dy) {
    const int ox = dx + kClothRadius, oy = dy + kClothRadius;
    return {
        o.spatial[oy][ox] * fast_exp(-tap_exponent(p, c, i, j, o.inv_distance[oy][ox])),
        {1.0f, p.nx[j] - p.nx[i], p.ny[j] - p.ny[i], p.nz[j] - p.nz[i], o.regressor[ox], o.regressor[oy],
         (p.depth[j] - p.depth[i]) * c.inv_depth_unit, o.square[ox], o.square[oy], o.regressor[ox] * o.regressor[oy]}};
}

// The regression's value from its weighted sums (xx: X^T W X's upper triangle, row by row;
// xy: X^T W y; yy: the weighted sum of the light's squared luminance), written to `out` when
// the fit is sound and fits: its residual within kClothMisfit times `noise`, the variance of the
// light's luminance at the pixel.
template <int kRegressors>
void solve(const float (&xx)[products(kRegressors)], const float (&xy)[kRegressors][3], float yy, float noise, V3& out,
           float* beta_out) {
    if (beta_out) beta_out[0] = std::numeric_limits<float>::quiet_NaN();
    Eigen::Matrix<double, kRegressors, kRegressors> m;
    int k = 0;
    for (int a = 0; a < kRegressors; ++a)
        for (int b = a; b < kRegressors; ++b) m(a, b) = m(b, a) = xx[k++];
    for (int a = 1; a < kRegressors; ++a) m(a, a) += kClothRidge;
    Eigen::Matrix<double, kRegressors, 3> rhs;
    for (int a = 0; a < kRegressors; ++a)
        for (int c = 0; c < 3; ++c) rhs(a, c) = xy[a][c];
    const Eigen::LLT<Eigen::Matrix<double, kRegressors, kRegressors>> fit(m);
    if (fit.info() != Eigen::Success) return;
    const Eigen::Matrix<double, kRegressors, 3> beta = fit.solve(rhs);
    const V3 value(float(beta(0, 0)), float(beta(0, 1)), float(beta(0, 2)));
    // The fit's weighted residual variance in luminance, (y^T W y - beta^T X^T W y) / sum W.
    const Eigen::Vector3d to_luminance = Eigen::Map<const Eigen::Vector3f>(kLuminanceWeights).cast<double>();
    const Eigen::Matrix<double, kRegressors, 1> beta_luminance = beta * to_luminance;
    const double residual = std::max(0.0, double(yy) - beta_luminance.dot(rhs * to_luminance)) / double(xx[0]);
    if (!(residual <= kClothMisfit * double(noise))) return;
    if (!value.allFinite() || value.minCoeff() < 0.0f) return;
    out = value;
    if (beta_out)
        for (int a = 0; a < kRegressors; ++a)
            for (int c = 0; c < 3; ++c) beta_out[3 * a + c] = float(beta(a, c));
}

// Pixel i's fit at (x, y), a tap at a time.
template <int kRegressors>
void regress_pixel(const Planes& p, const Offsets& o, int x, int y, V3& out) {
    const std::size_t i = std::size_t(y) * p.w + x;
    float xx[products(kRegressors)] = {};
    float xy[kRegressors][3] = {};
    float yy = 0.0f;
    const Centre at = centre(p, i);
    for (int dy = -kClothRadius; dy <= kClothRadius; ++dy) {
        const int qy = y + dy;
        if (qy < 0 || qy >= p.h) continue;
        for (int dx = -kClothRadius; dx <= kClothRadius; ++dx) {
            const int qx = x + dx;
            if (qx < 0 || qx >= p.w) continue;
            const std::size_t j = std::size_t(qy) * p.w + qx;
            if (!alike(p, i, j)) continue;
            const Tap t = tap(p, o, at, i, j, dx, dy);
            const float l[3] = {p.red[j], p.green[j], p.blue[j]};
            int k = 0;
            for (int a = 0; a < kRegressors; ++a) {
                const float wa = t.weight * t.r[a];
                for (int b = a; b < kRegressors; ++b) xx[k++] += wa * t.r[b];
                for (int c = 0; c < 3; ++c) xy[a][c] += wa * l[c];
            }
            const float lum = luminance(V3(l[0], l[1], l[2]));
            yy += t.weight * lum * lum;
        }
    }
    solve<kRegressors>(xx, xy, yy, p.fitted_variance[i], out, p.betas ? p.betas + kBetaFloats * i : nullptr);
}

#if defined(__SSE2__)
// Pixels i..i+3 of row y at once, every tap inside the image: each lane the same operations
// as regress_pixel in the same order, so the same floats.
template <int kRegressors>
void regress_four(const Planes& p, const Offsets& o, int x, int y, V3* out) {
    const std::size_t i = std::size_t(y) * p.w + x;
    const auto load = [](const float* a) { return _mm_loadu_ps(a); };
    const __m128 depth_i = load(p.depth + i), guide_i = load(p.guide + i), variance_i = load(p.variance + i);
    const __m128 ax_i = load(p.ax + i), ay_i = load(p.ay + i), az_i = load(p.az + i);
    const __m128 nx_i = load(p.nx + i), ny_i = load(p.ny + i), nz_i = load(p.nz + i);
    const __m128 inv_tolerance = _mm_div_ps(
        _mm_set1_ps(1.0f), _mm_add_ps(_mm_mul_ps(_mm_set1_ps(p.depth_tolerance), depth_i), _mm_set1_ps(1e-6f)));
    const __m128 inv_depth_unit = _mm_div_ps(
        _mm_set1_ps(1.0f), _mm_add_ps(_mm_mul_ps(_mm_set1_ps(kDepthRegressorUnit), depth_i), _mm_set1_ps(1e-6f)));
    const __m128 relative = _mm_mul_ps(_mm_set1_ps(kColourRelative), guide_i);
    const __m128 scale_floor = _mm_add_ps(_mm_mul_ps(relative, relative), _mm_set1_ps(1e-8f));
    const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    const __m128 same_albedo = _mm_set1_ps(kRegressionSameAlbedo);
    const __m128 colour_sigma2 = _mm_set1_ps(kColourSigma * kColourSigma);
    const __m128 sign_bit = _mm_set1_ps(-0.0f);
    __m128 xx[products(kRegressors)], xy[kRegressors][3];
    __m128 yy = _mm_setzero_ps();
    for (__m128& s : xx) s = _mm_setzero_ps();
    for (auto& row : xy)
        for (__m128& s : row) s = _mm_setzero_ps();
    for (int dy = -kClothRadius; dy <= kClothRadius; ++dy) {
        const int qy = y + dy;
        if (qy < 0 || qy >= p.h) continue;
        for (int dx = -kClothRadius; dx <= kClothRadius; ++dx) {
            const std::size_t j = std::size_t(qy) * p.w + std::size_t(x + dx);
            const __m128 taken = _mm_and_ps(
                _mm_castsi128_ps(
                    _mm_cmpeq_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p.cloth + j)), _mm_set1_epi32(1))),
                _mm_and_ps(
                    _mm_cmplt_ps(_mm_and_ps(_mm_sub_ps(load(p.ax + j), ax_i), abs_mask), same_albedo),
                    _mm_and_ps(_mm_cmplt_ps(_mm_and_ps(_mm_sub_ps(load(p.ay + j), ay_i), abs_mask), same_albedo),
                               _mm_cmplt_ps(_mm_and_ps(_mm_sub_ps(load(p.az + j), az_i), abs_mask), same_albedo))));
            if (_mm_movemask_ps(taken) == 0) continue;
            const __m128 depth_j = load(p.depth + j);
            const __m128 difference = _mm_sub_ps(load(p.guide + j), guide_i);
            const __m128 colour = _mm_div_ps(
                _mm_mul_ps(difference, difference),
                _mm_add_ps(_mm_mul_ps(colour_sigma2, _mm_add_ps(variance_i, load(p.variance + j))), scale_floor));
            const __m128 exponent =
                _mm_add_ps(_mm_mul_ps(_mm_mul_ps(_mm_and_ps(_mm_sub_ps(depth_j, depth_i), abs_mask), inv_tolerance),
                                      _mm_set1_ps(o.inv_distance[dy + kClothRadius][dx + kClothRadius])),
                           colour);
            const __m128 weight =
                _mm_and_ps(taken, _mm_mul_ps(_mm_set1_ps(o.spatial[dy + kClothRadius][dx + kClothRadius]),
                                             fast_exp4(_mm_xor_ps(exponent, sign_bit))));
            const __m128 r[kStillRegressors] = {
                _mm_set1_ps(1.0f),
                _mm_sub_ps(load(p.nx + j), nx_i),
                _mm_sub_ps(load(p.ny + j), ny_i),
                _mm_sub_ps(load(p.nz + j), nz_i),
                _mm_set1_ps(o.regressor[dx + kClothRadius]),
                _mm_set1_ps(o.regressor[dy + kClothRadius]),
                _mm_mul_ps(_mm_sub_ps(depth_j, depth_i), inv_depth_unit),
                _mm_set1_ps(o.square[dx + kClothRadius]),
                _mm_set1_ps(o.square[dy + kClothRadius]),
                _mm_set1_ps(o.regressor[dx + kClothRadius] * o.regressor[dy + kClothRadius])};
            const __m128 l[3] = {load(p.red.data() + j), load(p.green.data() + j), load(p.blue.data() + j)};
            int k = 0;
            for (int a = 0; a < kRegressors; ++a) {
                const __m128 wa = _mm_mul_ps(weight, r[a]);
                for (int b = a; b < kRegressors; ++b) xx[k] = _mm_add_ps(xx[k], _mm_mul_ps(wa, r[b])), ++k;
                for (int c = 0; c < 3; ++c) xy[a][c] = _mm_add_ps(xy[a][c], _mm_mul_ps(wa, l[c]));
            }
            const __m128 lum = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(kLuminanceWeights[0]), l[0]),
                                                     _mm_mul_ps(_mm_set1_ps(kLuminanceWeights[1]), l[1])),
                                          _mm_mul_ps(_mm_set1_ps(kLuminanceWeights[2]), l[2]));
            yy = _mm_add_ps(yy, _mm_mul_ps(weight, _mm_mul_ps(lum, lum)));
        }
    }
    alignas(16) float lanes_xx[products(kRegressors)][4], lanes_xy[kRegressors][3][4], lanes_yy[4];
    _mm_store_ps(lanes_yy, yy);
    for (int k = 0; k < products(kRegressors); ++k) _mm_store_ps(lanes_xx[k], xx[k]);
    for (int a = 0; a < kRegressors; ++a)
        for (int c = 0; c < 3; ++c) _mm_store_ps(lanes_xy[a][c], xy[a][c]);
    for (int lane = 0; lane < 4; ++lane) {
        if (!p.cloth[i + std::size_t(lane)]) continue;
        float sums_xx[products(kRegressors)], sums_xy[kRegressors][3];
        for (int k = 0; k < products(kRegressors); ++k) sums_xx[k] = lanes_xx[k][lane];
        for (int a = 0; a < kRegressors; ++a)
            for (int c = 0; c < 3; ++c) sums_xy[a][c] = lanes_xy[a][c][lane];
        const std::size_t pixel = i + std::size_t(lane);
        solve<kRegressors>(sums_xx, sums_xy, lanes_yy[lane], p.fitted_variance[pixel], out[lane],
                           p.betas ? p.betas + kBetaFloats * pixel : nullptr);
    }
}
#endif

template <int kRegressors>
void regress_rows(const Planes& p, const Offsets& offsets, std::vector<V3>& out) {
    tbb::parallel_for(tbb::blocked_range<int>(0, p.h), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y) {
            const std::size_t row = std::size_t(y) * p.w;
            int x = 0;
            while (x < p.w) {
#if defined(__SSE2__)
                // Four pixels at a time where all their taps lie inside the row.
                if (x >= kClothRadius && x + 4 + kClothRadius <= p.w) {
                    const std::int32_t* c = p.cloth + row + x;
                    if (c[0] | c[1] | c[2] | c[3]) regress_four<kRegressors>(p, offsets, x, y, &out[row + x]);
                    x += 4;
                    continue;
                }
#endif
                if (p.cloth[row + x]) regress_pixel<kRegressors>(p, offsets, x, y, out[row + x]);
                ++x;
            }
        }
    });
}
// Each pixel whose own fit fits, the weighted mean of the fits about it and its neighbours,
// each evaluated at the pixel with the weight that fit gave the pixel as a tap (Bitterli et
// al. 2016's averaging of overlapping windows): one fit's noise is shared by the neighbours
// whose windows overlap it, the mean of many is less noisy.  A neighbour whose fit failed adds
// nothing, one whose value at the pixel disagrees with the pixel's own fit little
// (kAgreement).
void average_fits(const Planes& p, const Offsets& o, std::vector<V3>& out) {
    const auto centres = std::make_unique_for_overwrite<Centre[]>(out.size());  // cloth pixels' only
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, out.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t j = r.begin(); j < r.end(); ++j)
            if (p.cloth[j]) centres[j] = centre(p, j);
    });
    tbb::parallel_for(tbb::blocked_range<int>(0, p.h), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
            for (int x = 0; x < p.w; ++x) {
                const std::size_t i = std::size_t(y) * p.w + x;
                if (!p.cloth[i] || std::isnan(p.betas[kBetaFloats * i])) continue;
                double sum[3] = {0.0, 0.0, 0.0}, weights = 0.0;
                const float* const own = p.betas + kBetaFloats * i;
                const float own_luminance = luminance(V3(own[0], own[1], own[2]));
                for (int dy = -kAverageRadius; dy <= kAverageRadius; ++dy) {
                    const int qy = y + dy;
                    if (qy < 0 || qy >= p.h) continue;
                    for (int dx = -kAverageRadius; dx <= kAverageRadius; ++dx) {
                        const int qx = x + dx;
                        if (qx < 0 || qx >= p.w) continue;
                        const std::size_t j = std::size_t(qy) * p.w + qx;
                        const float* const beta = p.betas + kBetaFloats * j;
                        if (!p.cloth[j] || !alike(p, j, i) || std::isnan(beta[0])) continue;
                        // Pixel i as a tap of j's fit, at (-dx, -dy) from j.
                        const Tap t = tap(p, o, centres[j], j, i, -dx, -dy);
                        float values[3];
                        for (int c = 0; c < 3; ++c) {
                            float value = 0.0f;
                            for (int k = 0; k < kStillRegressors; ++k) value += t.r[k] * beta[3 * k + c];
                            values[c] = value;
                        }
                        const float d = luminance(V3(values[0], values[1], values[2])) - own_luminance;
                        const float weight = t.weight * std::exp(-d * d / (kAgreement * p.fitted_variance[i] + 1e-12f));
                        for (int c = 0; c < 3; ++c) sum[c] += double(weight) * values[c];
                        weights += weight;
                    }
                }
                const V3 mean(float(sum[0] / weights), float(sum[1] / weights), float(sum[2] / weights));
                if (mean.allFinite() && mean.minCoeff() >= 0.0f) out[i] = mean;
            }
    });
}
}  // namespace

void regress_cloth(const ClothRegressionInput& in, std::vector<V3>& out) {
    Planes p;
    p.w = in.width, p.h = in.height;
    p.depth_tolerance = in.depth_regressor ? kStillDepthTolerance : kFrameDepthTolerance;
    p.guide = in.guide->data(), p.variance = in.variance->data(), p.fitted_variance = in.fitted_variance->data();
    p.nx = in.nx->data(), p.ny = in.ny->data(), p.nz = in.nz->data(), p.depth = in.depth->data();
    p.ax = in.ax->data(), p.ay = in.ay->data(), p.az = in.az->data(), p.cloth = in.cloth->data();
    const std::vector<V3>& light = *in.light;
    p.red.resize(light.size()), p.green.resize(light.size()), p.blue.resize(light.size());
    for (std::size_t i = 0; i < light.size(); ++i)
        p.red[i] = light[i].x(), p.green[i] = light[i].y(), p.blue[i] = light[i].z();
    const Offsets offsets(in.spatial_sigma);
    std::unique_ptr<float[]> betas;
    if (in.depth_regressor && in.average_fits) {
        betas = std::make_unique_for_overwrite<float[]>(light.size() * kBetaFloats);
        p.betas = betas.get();
    }
    if (in.depth_regressor) {
        regress_rows<kStillRegressors>(p, offsets, out);
        if (in.own_fits)
            for (std::size_t i = 0; i < out.size(); ++i)
                if (p.cloth[i]) (*in.own_fits)[i] = out[i];
        if (p.betas) average_fits(p, offsets, out);
    } else
        regress_rows<kFrameRegressors>(p, offsets, out);
}

}  // namespace foldcast::render
