// The paper's iteration, read as literally as its description allows (docs/drape.md, "The
// paper's closure", says where it is ambiguous and which reading this is):
//   a_0 = 1.01 h, a_n = 0.01 h, zmax = 0.01 h to start;
//   each step raises zmax by 1 % and takes the (real) fold count n that the centre fibre
//   holds, sum_{i=1..n} sqrt((a_{i-1} - a_i)^2 + (2 zmax)^2) = h with a_i = a_0 Q^-i, Q from
//   the critical-stress equation, so a_n = a_0 Q^-n;
//   it stops once the top edge (a_n, zmax), measured by Simpson's rule, is within 5 % of L;
//   then n is rounded to the nearest integer and Q = (a_0 / a_n)^(1/n).
// zmax is the variable that moves: a deeper fold lets fewer folds fit the fibre, so a_n grows
// and with it the top edge, monotonically, and the first step inside the 5 % band ends it.
#include "paper_closure.hpp"

#include "fold_geometry.hpp"

#include <algorithm>
#include <cmath>

#include "foldcast/core/math.hpp"

namespace foldcast::drape::detail {

namespace {

constexpr double kStartFraction = 0.01;    // a_n = zmax = 0.01 h, a_0 = (1 + 0.01) h
constexpr double kStepFactor = 1.01;       // zmax grows by 1 % a step
constexpr double kLengthTolerance = 0.05;  // the top edge within 5 % of L ends the iteration
constexpr int kSimpsonIntervals = 32;
constexpr int kMaxSteps = 2000;  // 1.01^2000: zmax would pass any cloth long before

// Length of the centre fibre's zig-zag through a real number of folds n: whole folds, then
// the fraction of the next (continuous in n, so the fibre equation has one root).
double fibre_length_m(double a0, double q, double folds, double zmax) {
    double length = 0.0;
    const int whole = static_cast<int>(folds);
    double upper = a0;
    for (int i = 1; i <= whole; ++i) {
        const double lower = upper / q;
        length += std::hypot(upper - lower, 2.0 * zmax);
        upper = lower;
    }
    const double part = folds - whole;
    if (part > 0.0) length += part * std::hypot(upper - upper / q, 2.0 * zmax);
    return length;
}

// The real n whose zig-zag is as long as the fibre h.  Each fold adds at least 2 zmax, so
// n <= h / (2 zmax) + 1 brackets the root.
double folds_on_fibre(double a0, double q, double zmax, double height_m) {
    double lo = 0.0, hi = height_m / (2.0 * zmax) + 1.0;
    for (int i = 0; i < 200 && hi - lo > 1e-12 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        (fibre_length_m(a0, q, mid, zmax) < height_m ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

}  // namespace

double top_edge_length_simpson_m(double span_m, double amplitude_m, int intervals) {
    const double k = kPi * amplitude_m / span_m;
    const auto speed = [&](double x) {
        const double s = std::sin(kPi * x / span_m);
        return std::sqrt(1.0 + k * k * s * s);
    };
    const double dx = span_m / intervals;
    double sum = speed(-0.5 * span_m) + speed(0.5 * span_m);
    for (int i = 1; i < intervals; ++i) sum += (i % 2 ? 4.0 : 2.0) * speed(-0.5 * span_m + i * dx);
    return sum * dx / 3.0;
}

FoldSolution solve_paper_closure(const ClothParams& bay, FoldSolution s) {
    const double h = bay.height_m, width = bay.width_m, span = bay.support_span_m();
    const double q = s.critical_Q;
    const double a0 = (1.0 + kStartFraction) * h;
    double zmax = kStartFraction * h, an = kStartFraction * h, folds_real = 0.0, top = span;
    int step = 0;
    for (; step < kMaxSteps; ++step) {
        folds_real = folds_on_fibre(a0, q, zmax, h);
        an = a0 * std::pow(q, -folds_real);
        top = top_edge_length_simpson_m(span, std::hypot(an, zmax), kSimpsonIntervals);
        if (std::abs(top - width) <= kLengthTolerance * width || top > width) break;
        zmax *= kStepFactor;
    }
    const int n = std::max(1, static_cast<int>(std::lround(folds_real)));
    s.closure = Closure::paper;
    s.closure_steps = step;
    s.regime = FoldSolution::Regime::wrinkled;
    s.folds = n;
    s.Q = std::pow(a0 / an, 1.0 / n);
    s.zmax_m = zmax;
    s.amplitudes_m.resize(std::size_t(n) + 1);
    for (int i = 0; i <= n; ++i) s.amplitudes_m[std::size_t(i)] = a0 * std::pow(s.Q, -i);
    s.amplitudes_m.back() = an;
    s.fold_length_m = zig_zag_length_m(s.amplitudes_m, zmax);
    s.feasible_folds = {n};
    // The paper's answer is within its 5 % bands, not a root: report how far it is from both
    // length equations (the top edge in closed form, the centre fibre).
    s.residual = std::max(std::abs(top_edge_length_m(span, std::hypot(an, zmax)) - width) / width,
                          std::abs(s.fold_length_m - h) / h);
    s.explanation = std::to_string(n) + (n == 1 ? " fold" : " folds") + " (the paper's closure): S = " +
                    format_number(s.stress_ratio) + " < 1 gives Q = " + format_number(q) + "; from a_0 = 1.01 h, zmax rose to " +
                    format_number(zmax) + " m in " + std::to_string(step) + " steps of 1 %, the centre fibre holding " +
                    format_number(folds_real) + " folds, until the top edge (Simpson, " + format_number(top) +
                    " m) was within 5 % of L = " + format_number(width) + " m; n rounded, Q = (a_0/a_n)^(1/n) = " + format_number(s.Q);
    return s;
}

}  // namespace foldcast::drape::detail
