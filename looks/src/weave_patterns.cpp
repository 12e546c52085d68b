// Yarn geometry of plain, twill, satin and jersey.  Woven: each cell of the yarn grid shows
// the warp or the weft on top; the top yarn has an elliptic-ish cross-section (cos profile)
// and bulges along its float, dipping where it goes under at the float's ends.  Knit: each
// cell is one V loop whose two legs lean towards each other.
#include "weave_patterns.hpp"

#include <cmath>
#include "foldcast/core/math.hpp"

namespace foldcast::looks::detail {
namespace {

// Height of a yarn's crown above the gaps, in yarn pitches.  With the cos profile the steepest
// flank slope is kYarnHeight * pi = 0.63 (32 degrees), typical of woven yarn cross-sections.
constexpr double kYarnHeight = 0.2;
// Share of a float's height kept at its ends, where the yarn dives under a crossing yarn.
constexpr double kFloatEndHeight = 0.6;
// Knit: how far each leg's centre moves across per course (the V's lean), in wale widths.
constexpr double kLegLean = 0.1;

long floor_index(double x) { return static_cast<long>(std::floor(x)); }
long positive_mod(long a, long n) { return ((a % n) + n) % n; }

bool warp_on_top(Pattern pattern, long i, long j) {  // i along u (weft index), j along v
    switch (pattern) {
        case Pattern::plain:
            return positive_mod(i + j, 2) == 0;
        case Pattern::twill_2_1:
            return positive_mod(i - j, 3) < 2;
        case Pattern::twill_3_1:
            return positive_mod(i - j, 4) < 3;
        // Warp-faced 5-harness satin, move number 2: each warp yarn goes under once every
        // five picks and the binding points of neighbouring yarns are two picks apart, so
        // they scatter instead of forming a twill line.
        case Pattern::satin_5:
            return positive_mod(i - 2 * j, 5) != 0;
        default:
            return true;
    }
}

// A yarn's surface at `across` in [-0.5, 0.5] from its centre line and `along` in [0, 1]
// through a float `float_yarns` long; slopes in yarn-pitch units.
struct Profile {
    double height, d_across, d_along;
};
Profile yarn_profile(double across, double along, int float_yarns) {
    const double lift = kFloatEndHeight + (1.0 - kFloatEndHeight) * std::sin(kPi * along);
    const double d_lift = (1.0 - kFloatEndHeight) * kPi * std::cos(kPi * along) / float_yarns;
    const double crown = std::cos(kPi * across);
    return {kYarnHeight * crown * lift, -kYarnHeight * kPi * std::sin(kPi * across) * lift,
            kYarnHeight * crown * d_lift};
}

float yarn_shading(double across, double along) {
    // Flanks and float ends are partly shadowed by the neighbouring yarns.
    return static_cast<float>((0.65 + 0.35 * std::cos(kPi * across)) * (0.85 + 0.15 * std::sin(kPi * along)));
}

YarnPoint woven(Pattern pattern, double x, double y) {
    const long i = floor_index(x), j = floor_index(y);
    const double fx = x - static_cast<double>(i), fy = y - static_cast<double>(j);
    const int max_float = pattern_period_yarns(pattern).maxCoeff();
    YarnPoint point;
    if (warp_on_top(pattern, i, j)) {
        // Warp float along u: find where it starts and ends on this warp yarn.
        long start = i, end = i;
        while (i - start < max_float && warp_on_top(pattern, start - 1, j)) --start;
        while (end - i < max_float && warp_on_top(pattern, end + 1, j)) ++end;
        const int length = static_cast<int>(end - start + 1);
        const double along = (x - static_cast<double>(start)) / length;
        const Profile profile = yarn_profile(fy - 0.5, along, length);
        point.slope_u = static_cast<float>(profile.d_along);
        point.slope_v = static_cast<float>(profile.d_across);
        point.albedo = yarn_shading(fy - 0.5, along);
        point.yarn = 1;
    } else {
        long start = j, end = j;
        while (j - start < max_float && !warp_on_top(pattern, i, start - 1)) --start;
        while (end - j < max_float && !warp_on_top(pattern, i, end + 1)) ++end;
        const int length = static_cast<int>(end - start + 1);
        const double along = (y - static_cast<double>(start)) / length;
        const Profile profile = yarn_profile(fx - 0.5, along, length);
        point.slope_u = static_cast<float>(profile.d_across);
        point.slope_v = static_cast<float>(profile.d_along);
        point.albedo = yarn_shading(fx - 0.5, along);
        point.weft = 1.0f;
        point.yarn = 2;
    }
    return point;
}

// Single jersey, technical face: wales along v, one V per wale (u) and course (v).  The
// legs' centres lean from 0.25/0.75 of the wale towards its middle as v grows, so the
// pair reads as a V; beyond a leg's width is the gap between legs and wales.
YarnPoint jersey(double x, double y) {
    const double fx = x - std::floor(x), fy = y - std::floor(y);
    const bool left = fx < 0.5;
    const double lean = left ? kLegLean : -kLegLean;
    const double centre = (left ? 0.25 : 0.75) + lean * (fy - 0.5);
    constexpr double kLegWidth = 0.5;  // wale widths, measured across u
    const double across = (fx - centre) / kLegWidth;
    YarnPoint point;
    if (std::abs(across) >= 0.5) {
        point.albedo = static_cast<float>(0.65 * (0.85 + 0.15 * std::sin(kPi * fy)));
        point.yarn = 0;
        return point;
    }
    const Profile profile = yarn_profile(across, fy, 1);
    // d(across)/du = 1/width; d(across)/dv = -lean/width.
    point.slope_u = static_cast<float>(profile.d_across / kLegWidth);
    point.slope_v = static_cast<float>(profile.d_across * (-lean / kLegWidth) + profile.d_along);
    point.albedo = yarn_shading(across, fy);
    point.yarn = 2;  // legs run along v
    return point;
}

}  // namespace

Pattern pattern_of(const Appearance& appearance) {
    switch (appearance.weave) {
        case Weave::plain:
            return Pattern::plain;
        case Weave::twill:
            return appearance.twill_float == 2 ? Pattern::twill_2_1 : Pattern::twill_3_1;
        case Weave::satin:
            return Pattern::satin_5;
        case Weave::knit:
            return Pattern::jersey;
        case Weave::none:
            break;
    }
    return Pattern::plain;
}

Eigen::Vector2i pattern_period_yarns(Pattern pattern) {
    switch (pattern) {
        case Pattern::plain:
            return {2, 2};
        case Pattern::twill_2_1:
            return {3, 3};
        case Pattern::twill_3_1:
            return {4, 4};
        case Pattern::satin_5:
            return {5, 5};
        default:
            return {1, 1};
    }
}

YarnPoint evaluate_pattern(Pattern pattern, double x, double y) {
    return pattern == Pattern::jersey ? jersey(x, y) : woven(pattern, x, y);
}

}  // namespace foldcast::looks::detail
