// Footprint filtering of the procedural weaves.  A pixel that covers a good part of a yarn
// cannot show the yarn structure; point-sampling it would alias (shimmer in turntables).  So:
//   footprint < kFourTapsAbove pitches: one sample (the pixel resolves the yarns);
//   above that: a 4-tap box filter over the footprint;
//   from kFadeStart to kFadeEnd pitches: blend towards the pattern's exact period average,
//   reached at kFadeEnd (one yarn per pixel: the yarns' fundamental is at 1/2 pixel^-1,
//   Nyquist) and held beyond.
// The albedo is normalised so its period average is 1: a distant cloth shows exactly the
// look's base colour, a close one the same colour on average.
#include "foldcast/looks/weave.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "weave_patterns.hpp"

namespace foldcast::looks {
namespace {

constexpr double kFourTapsAbove = 0.1;  // footprint in yarn pitches
constexpr double kFadeStart = 0.25;
constexpr double kFadeEnd = 1.0;

// Period averages of each pattern, by the midpoint rule on a fine grid (exact enough: the
// integrands are smooth within cells).
struct PatternStats {
    double mean_albedo = 1.0;
    double mean_weft = 0.0;
    double slope_variance = 0.0;  // mean of slope_u^2 + slope_v^2 (the mean slope is 0)
};

PatternStats integrate(detail::Pattern pattern) {
    constexpr int kSamplesPerYarn = 64;
    const Eigen::Vector2i period = detail::pattern_period_yarns(pattern);
    const int nx = period.x() * kSamplesPerYarn, ny = period.y() * kSamplesPerYarn;
    double albedo = 0.0, weft = 0.0, slope2 = 0.0;
    for (int b = 0; b < ny; ++b)
        for (int a = 0; a < nx; ++a) {
            const auto point =
                detail::evaluate_pattern(pattern, (a + 0.5) / kSamplesPerYarn, (b + 0.5) / kSamplesPerYarn);
            albedo += point.albedo;
            weft += point.weft;
            slope2 += double(point.slope_u) * point.slope_u + double(point.slope_v) * point.slope_v;
        }
    const double n = double(nx) * ny;
    return {albedo / n, weft / n, slope2 / n};
}

const PatternStats& stats(detail::Pattern pattern) {
    static const auto table = [] {
        std::array<PatternStats, static_cast<size_t>(detail::Pattern::count)> all;
        for (size_t p = 0; p < all.size(); ++p) all[p] = integrate(static_cast<detail::Pattern>(p));
        return all;
    }();
    return table[static_cast<size_t>(pattern)];
}

double smoothstep(double edge0, double edge1, double x) {
    const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

}  // namespace

WeaveSample sample_weave(const Appearance& appearance, Eigen::Vector2d uv_m, double footprint_m) {
    WeaveSample sample;
    if (appearance.weave == Weave::none || !(appearance.repeat_mm > 0.0)) return sample;
    const detail::Pattern pattern = detail::pattern_of(appearance);
    const PatternStats& average = stats(pattern);
    const double pitch_m = appearance.repeat_mm * 1e-3;
    const double x = uv_m.x() / pitch_m, y = uv_m.y() / pitch_m;
    const double footprint = std::max(0.0, footprint_m) / pitch_m;  // in yarn pitches
    const double fade = smoothstep(kFadeStart, kFadeEnd, footprint);
    const double bump = appearance.bump_strength;

    double albedo = average.mean_albedo, slope_u = 0.0, slope_v = 0.0, weft = average.mean_weft;
    int yarn = 0;
    if (fade < 1.0) {
        if (footprint <= kFourTapsAbove) {
            const auto point = detail::evaluate_pattern(pattern, x, y);
            albedo = point.albedo;
            slope_u = point.slope_u;
            slope_v = point.slope_v;
            weft = point.weft;
            yarn = point.yarn;
        } else {
            // Box filter of width `footprint`: the 2 x 2 midpoint rule.
            const double h = 0.25 * footprint;
            albedo = slope_u = slope_v = weft = 0.0;
            int first_yarn = -1;
            bool same_yarn = true;
            for (const double dy : {-h, h})
                for (const double dx : {-h, h}) {
                    const auto point = detail::evaluate_pattern(pattern, x + dx, y + dy);
                    albedo += 0.25 * point.albedo;
                    slope_u += 0.25 * point.slope_u;
                    slope_v += 0.25 * point.slope_v;
                    weft += 0.25 * point.weft;
                    if (first_yarn < 0) first_yarn = point.yarn;
                    same_yarn = same_yarn && point.yarn == first_yarn;
                }
            yarn = same_yarn ? first_yarn : 0;
        }
        albedo += fade * (average.mean_albedo - albedo);
        weft += fade * (average.mean_weft - weft);
        slope_u *= 1.0 - fade;
        slope_v *= 1.0 - fade;
        if (fade > 0.5) yarn = 0;
    }
    sample.albedo_scale = static_cast<float>(albedo / average.mean_albedo);
    sample.weft_cover = static_cast<float>(weft);
    sample.yarn = yarn;
    sample.normal =
        Eigen::Vector3f(static_cast<float>(-bump * slope_u), static_cast<float>(-bump * slope_v), 1.0f).normalized();
    sample.slope_variance = static_cast<float>(fade * bump * bump * average.slope_variance);
    return sample;
}

Eigen::Vector3f weave_albedo(const Appearance& appearance, const WeaveSample& sample) {
    const Eigen::Vector3f& warp = appearance.base_colour;
    const Eigen::Vector3f& weft = appearance.weft_colour ? *appearance.weft_colour : warp;
    return ((1.0f - sample.weft_cover) * warp + sample.weft_cover * weft) * sample.albedo_scale;
}

Eigen::Vector2i weave_period_yarns(const Appearance& appearance) {
    if (appearance.weave == Weave::none) return {1, 1};
    return detail::pattern_period_yarns(detail::pattern_of(appearance));
}

}  // namespace foldcast::looks
