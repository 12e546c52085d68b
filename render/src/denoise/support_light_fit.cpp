#include "support_light_fit.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "foldcast/core/colour.hpp"
#include "tap_weights.hpp"

namespace foldcast::render {
namespace {

// The line of taps and its Gaussian weights (sigma half the radius).  Default scene at
// 320x180, 16 spp + denoise, the rod's squared error (seeds 1-3, x1e-6; 7.91 without this
// stage): a straight line at radius 8 / 12 / 16 6.73 / 6.66 / 6.86, the quadratic at 12 / 16 /
// 20 6.69 / 6.50 / 6.47 (docs/benchmarks.md, "The supports' regression").
constexpr int kSupportRadius = 16;
constexpr float kSupportSigma = 8.0f;
// At least this many taps on the line (the pixel's own included) must be of the same support
// and albedo: the clips, five pixels wide, are left to the passes.  Fitted along their short
// runs they lost (radius 12, no such test: the garment's box 6.23 -> 6.36, the other edges
// 0.35 -> 0.44); at least 13 / 20 / 25 of 25 taps: the rod 6.95 / 7.19 / 7.23, the box 6.23.
constexpr int kMinRun = kSupportRadius + 1;
constexpr int kRegressors = 3;   // 1, the offset and its square (in units of the radius)
constexpr double kSupportRidge = 1e-3;  // on the slopes, relative to the weights' sum
// A tap's depth may differ by this share of the pixel's depth per pixel of distance (exp(-1)).
constexpr float kSupportDepthTolerance = 0.01f;
// How far the fit's residual may go beyond the light's noise before the pixel gives way to the
// a-trous result, exp(-residual / (kSupportMisfit noise)): a hard cut at 16 / 32 / 64 / 128 left the
// rod 6.95 / 6.86 / 6.80 / 6.74, the blend at 16 / 64 / 256 6.96 / 6.66 / 6.69 (straight line,
// radius 12); with the quadratic at radius 16, the blend at 32 / 64 6.68 / 6.50.
constexpr double kSupportMisfit = 64.0;
// What the pixel gives way to where the fit does not follow: a straight line over the nearest
// taps along the axis (Gaussian sigma kShortSigma, out to kShortRadius), with no colour or
// depth weight, rather than the a-trous result.  At a highlight's edge (the light rising
// tenfold in 6-8 pixels) the passes keep the 16-spp pixels' scatter; the short line follows
// the rise and still averages about four taps.  The rod's squared error (x1e-6) at 320x180,
// seeds 1-3: 6.49 -> 6.10 with sigma 0.7, chosen on those three seeds alone; over seeds 1-10,
// sigma 0.7 / 1.0 / 1.4 / 2.0 left 8.91 / 8.69 / 8.60 / 8.58.  At 640x360 (seeds 1-3) sigma 1.4
// left 2.72 against 0.7's 2.78 and 2.8's (radius 4) 2.86, so the width stays in pixels
// (docs/benchmarks.md, "The supports' regression" and "The short line's width").
constexpr int kShortRadius = 2;
constexpr float kShortSigma = 1.4f;

struct Sums {
    Eigen::Matrix3d xx = Eigen::Matrix3d::Zero();
    Eigen::Matrix<double, kRegressors, 3> xy = Eigen::Matrix<double, kRegressors, 3>::Zero();
    double yy = 0.0;  // the weighted sum of the light's squared luminance
    int run = 0;
    // The short line's: regressors 1 and the offset (in units of kShortRadius).
    Eigen::Matrix2d short_xx = Eigen::Matrix2d::Zero();
    Eigen::Matrix<double, 2, 3> short_xy = Eigen::Matrix<double, 2, 3>::Zero();
};

}  // namespace

void regress_supports(const SupportRegressionInput& in, std::vector<V3>& out) {
    const int w = in.width, h = in.height;
    const std::vector<std::int32_t>& support = *in.support;
    const std::vector<float>&nx = *in.nx, &ny = *in.ny, &nz = *in.nz, &turning = *in.turning;
    const std::vector<float>&ax = *in.ax, &ay = *in.ay, &az = *in.az, &depth = *in.depth;
    const std::vector<float>&guide = *in.guide, &variance = *in.variance;
    const auto at = [w](int x, int y) { return std::size_t(y) * w + x; };
    // How much the normal and the coverage change between two pixels: across the support they
    // turn through the cylinder and from backdrop to support, along it they hardly change.
    const auto change = [&](std::size_t i, std::size_t j) {
        const float a = nx[i] - nx[j], b = ny[i] - ny[j], c = nz[i] - nz[j], t = turning[i] - turning[j];
        return a * a + b * b + c * c + t * t;
    };
    const Eigen::Vector3d to_luminance = Eigen::Map<const Eigen::Vector3f>(kLuminanceWeights).cast<double>();
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = at(x, y);
                if (!support[i]) continue;
                const bool along_row = change(at(std::max(0, x - 1), y), at(std::min(w - 1, x + 1), y)) <=
                                       change(at(x, std::max(0, y - 1)), at(x, std::min(h - 1, y + 1)));
                Sums s;
                for (int d = -kSupportRadius; d <= kSupportRadius; ++d) {
                    const int qx = along_row ? x + d : x, qy = along_row ? y : y + d;
                    if (qx < 0 || qx >= w || qy < 0 || qy >= h) continue;
                    const std::size_t j = at(qx, qy);
                    if (!support[j] || std::abs(ax[j] - ax[i]) >= kRegressionSameAlbedo ||
                        std::abs(ay[j] - ay[i]) >= kRegressionSameAlbedo ||
                        std::abs(az[j] - az[i]) >= kRegressionSameAlbedo)
                        continue;
                    ++s.run;
                    const float mix = std::abs(turning[j] - turning[i]);
                    if (std::abs(d) <= kShortRadius) {
                        float es = float(d * d) / (2.0f * kShortSigma * kShortSigma);
                        if (mix > kMixDeadZone) es += kMixScale * (mix - kMixDeadZone);
                        if (es <= kMaxExponent) {
                            const double ws = std::exp(-double(es)), us = double(d) / kShortRadius;
                            const Eigen::Vector2d r(1.0, us);
                            s.short_xx.noalias() += ws * r * r.transpose();
                            s.short_xy.noalias() += ws * r * (*in.light)[j].cast<double>().transpose();
                        }
                    }
                    float e = float(d * d) / (2.0f * kSupportSigma * kSupportSigma);
                    if (mix > kMixDeadZone) e += kMixScale * (mix - kMixDeadZone);
                    if (d != 0)
                        e += std::abs(depth[j] - depth[i]) / (kSupportDepthTolerance * depth[i] * float(std::abs(d)));
                    const float difference = guide[j] - guide[i];
                    const float scale2 = kColourSigma * kColourSigma * (variance[i] + variance[j]) +
                                         kColourRelative * kColourRelative * guide[i] * guide[i] + 1e-12f;
                    e += difference * difference / scale2;
                    if (e > kMaxExponent) continue;
                    const double wt = std::exp(-double(e)), u = double(d) / kSupportRadius;
                    const Eigen::Vector3d r(1.0, u, u * u);
                    const V3& l = (*in.light)[j];
                    s.xx.noalias() += wt * r * r.transpose();
                    s.xy.noalias() += wt * r * l.cast<double>().transpose();
                    const double lum = luminance(l);
                    s.yy += wt * lum * lum;
                }
                if (s.run < kMinRun) continue;
                for (int a = 1; a < kRegressors; ++a) s.xx(a, a) += kSupportRidge * s.xx(0, 0);
                const Eigen::LLT<Eigen::Matrix3d> fit(s.xx);
                if (fit.info() != Eigen::Success) continue;
                const Eigen::Matrix<double, kRegressors, 3> beta = fit.solve(s.xy);
                const V3 value(float(beta(0, 0)), float(beta(0, 1)), float(beta(0, 2)));
                if (!value.allFinite() || value.minCoeff() < 0.0f) continue;
                // The fit's weighted residual variance in luminance, (y^T W y - beta^T X^T W y) / sum W.
                const double residual =
                    std::max(0.0, s.yy - (beta * to_luminance).dot(s.xy * to_luminance)) / s.xx(0, 0);
                const float alpha =
                    float(std::exp(-residual / (kSupportMisfit * double((*in.fitted_variance)[i]) + 1e-20)));
                V3 fallback = out[i];
                s.short_xx(1, 1) += kSupportRidge * s.short_xx(0, 0);
                const Eigen::LLT<Eigen::Matrix2d> short_fit(s.short_xx);
                if (short_fit.info() == Eigen::Success) {
                    const Eigen::Matrix<double, 2, 3> b = short_fit.solve(s.short_xy);
                    const V3 line(float(b(0, 0)), float(b(0, 1)), float(b(0, 2)));
                    if (line.allFinite() && line.minCoeff() >= 0.0f) fallback = line;
                }
                out[i] = alpha * value + (1.0f - alpha) * fallback;
            }
    });
}

}  // namespace foldcast::render
