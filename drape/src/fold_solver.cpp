// The tension-field fold solve (DESIGN.md "drape"): Q from the critical-stress equation,
// then for each fold count n the top-edge and centre-fibre length equations.
//
// Reduction to one unknown: the top edge y = a_n cos, z = zmax cos has amplitude
// A = sqrt(a_n^2 + zmax^2), and its length equation fixes A alone (top_edge_amplitude_m).
// With a_0 = b as the unknown (a_i = b Q^-i, zmax^2 = A^2 - b^2 Q^-2n) and s = b^2, the
// centre fibre equation reads
//   F_n(s) = sum_{i=1..n} sqrt(4 A^2 + s c_i) - h = 0,   c_i = (Q-1)^2 Q^-2i - 4 Q^-2n,
// a sum of square roots of functions linear in s: F_n is concave in s.  So on the physical
// interval 0 <= b <= A Q^n (zmax real) it has at most two roots, one on each side of its
// maximum; both are found by safeguarded Newton.  F_n grows with n at every b (a larger n
// lowers a_n, which deepens zmax, and adds a term), and so does its interval, so once
// F_n > 0 at both ends (hence everywhere) no larger n can solve the equations: the scan stops.
// Rule for n: the lowest fold line nearest the hem, i.e. the largest n whose solution keeps
// a_0 <= h; when no n does, the solved n with the smallest a_0.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "foldcast/core/error.hpp"
#include "foldcast/drape.hpp"
#include "root_finding.hpp"

namespace foldcast::drape {

namespace {

// More folds than this are below any useful grid resolution; the scan stops there.
constexpr int kMaxFolds = 1000;
constexpr double kRootTolerance = 1e-13;  // |F| / h at which a root is accepted

std::string fmt(double v, int precision = 4) {
    std::ostringstream s;
    s.precision(precision);
    s << v;
    return s.str();
}

class FibreEquation {
public:
    FibreEquation(double slack_amplitude_m, double height_m, double q, int folds)
        : a_(slack_amplitude_m), h_(height_m), q_(q), folds_(folds) {
        const double log_q = std::log(q);
        inv_q_n_ = std::exp(-folds * log_q);
        // b <= A Q^n keeps zmax real.  Fold lines 100 h below the hem are no answer either;
        // the cap keeps Q^n finite, and F_n > 0 at both ends stays a valid stop for the scan.
        const double log_limit = std::log(a_) + folds * log_q;
        const double cap = 100.0 * h_;
        b_hi_ = log_limit >= std::log(cap) ? cap : std::exp(log_limit);
        r2_.resize(static_cast<std::size_t>(folds));
        for (int i = 1; i <= folds; ++i) {
            const double r = (q - 1.0) * std::exp(-i * log_q);  // (a_{i-1} - a_i) / a_0
            r2_[static_cast<std::size_t>(i - 1)] = r * r;
        }
    }

    double s_hi() const { return b_hi_ * b_hi_; }

    // F(s) and F'(s), F''(s).
    void evaluate(double s, double& f, double& df, double& ddf) const {
        const double z2 = std::max(0.0, a_ * a_ - s * inv_q_n_ * inv_q_n_);  // zmax^2
        const double c_z = -4.0 * inv_q_n_ * inv_q_n_;
        f = -h_;
        df = 0.0;
        ddf = 0.0;
        for (double r2 : r2_) {
            const double term = std::sqrt(s * r2 + 4.0 * z2);
            const double c = r2 + c_z;
            f += term;
            if (term > 0.0) {
                df += 0.5 * c / term;
                ddf -= 0.25 * c * c / (term * term * term);
            }
        }
    }
    double value(double s) const {
        double f, df, ddf;
        evaluate(s, f, df, ddf);
        return f;
    }

    // Amplitudes a_0..a_n and zmax for a_0 = b.
    void shape(double b, std::vector<double>& amplitudes, double& zmax) const {
        amplitudes.resize(static_cast<std::size_t>(folds_) + 1);
        for (int i = 0; i <= folds_; ++i)
            amplitudes[static_cast<std::size_t>(i)] = b * std::pow(q_, -i);
        const double an = b * inv_q_n_;
        zmax = std::sqrt(std::max(0.0, a_ * a_ - an * an));
    }

private:
    double a_, h_, q_;
    int folds_;
    double inv_q_n_ = 1.0, b_hi_ = 0.0;
    std::vector<double> r2_;
};

struct Residuals {
    double top = 0.0, fibre = 0.0;
    double max() const { return std::max(top, fibre); }
};

Residuals residuals(const ClothParams& p, const std::vector<double>& amplitudes, double zmax) {
    Residuals r;
    const double an = amplitudes.back();
    r.top = std::abs(top_edge_length_m(p.support_span_m(), std::hypot(an, zmax)) - p.width_m) /
            p.width_m;
    double fibre = 0.0;
    for (std::size_t i = 1; i < amplitudes.size(); ++i)
        fibre += std::hypot(amplitudes[i - 1] - amplitudes[i], 2.0 * zmax);
    r.fibre = amplitudes.size() > 1 ? std::abs(fibre - p.height_m) / p.height_m : 0.0;
    return r;
}

struct CandidateSolve {
    FoldCandidate candidate;
    std::vector<double> amplitudes;
    bool stop_scan = false;  // no larger n can be feasible
};

CandidateSolve solve_candidate(const ClothParams& p, double slack_a, double q, int n) {
    CandidateSolve out;
    FoldCandidate& c = out.candidate;
    c.folds = n;
    const double h = p.height_m;
    const FibreEquation eq(slack_a, h, q, n);
    const double s_hi = eq.s_hi();
    const double f0 = eq.value(0.0), f1 = eq.value(s_hi);
    const double tol = kRootTolerance * h;

    // Peak of the concave F: where F' changes sign, else an end of the interval.
    double s_peak;
    {
        double f, d0, d1, ddf;
        eq.evaluate(0.0, f, d0, ddf);
        eq.evaluate(s_hi, f, d1, ddf);
        if (d0 <= 0.0)
            s_peak = 0.0;
        else if (d1 >= 0.0)
            s_peak = s_hi;
        else
            s_peak = detail::newton_bracketed(
                         [&](double s, double& g, double& dg) {
                             double fv;
                             eq.evaluate(s, fv, g, dg);
                         },
                         0.0, s_hi, 0.0, 200)
                         .x;
    }
    const double f_peak = eq.value(s_peak);
    if (f0 > tol && f1 > tol) {
        c.why_not = "even the shortest zig-zag of " + std::to_string(n) + " folds (" +
                    fmt(std::min(f0, f1) + h) + " m) is longer than the height " + fmt(h) +
                    " m: too many folds";
        out.stop_scan = true;
        return out;
    }
    if (f_peak < -tol) {
        c.why_not = "the longest zig-zag of " + std::to_string(n) + " folds (" +
                    fmt(f_peak + h) + " m) is shorter than the height " + fmt(h) +
                    " m: too few folds";
        return out;
    }
    // Up to two roots, one on each side of the peak.
    const auto f_df = [&](double s, double& f, double& df) {
        double ddf;
        eq.evaluate(s, f, df, ddf);
    };
    std::vector<double> roots;  // values of b = a_0, ascending
    if (f0 <= tol) roots.push_back(std::sqrt(std::max(0.0, detail::newton_bracketed(f_df, 0.0, s_peak, tol).x)));
    if (f1 <= tol) roots.push_back(std::sqrt(std::max(0.0, detail::newton_bracketed(f_df, s_peak, s_hi, tol).x)));
    // Physical roots: b > 0 (fold lines that sag) and zmax > 0 (real folds).
    std::vector<double> physical;
    for (double b : roots) {
        std::vector<double> amplitudes;
        double zmax;
        eq.shape(b, amplitudes, zmax);
        if (b > 0.0 && zmax > 1e-9 * slack_a) physical.push_back(b);
    }
    if (physical.empty()) {
        c.why_not = roots.front() > 0.0 ? "the only solution has zmax = 0 (a flat sag, no folds)"
                                        : "the only solution has a_0 = 0 (fold lines that do not sag)";
        return out;
    }
    // Prefer a root with the lowest fold line inside the cloth (a_0 <= h) and, of two, the
    // larger a_0 (fold lines hanging lower: less potential energy); otherwise the root whose
    // lowest fold line is nearest the hem.
    double b = physical.front();
    for (double r : physical)
        if (r <= h) b = r;
    double zmax;
    eq.shape(b, out.amplitudes, zmax);
    c.solved = true;
    c.lowest_amplitude_m = out.amplitudes.front();
    c.top_amplitude_m = out.amplitudes.back();
    c.zmax_m = zmax;
    c.residual = residuals(p, out.amplitudes, zmax).max();
    if (b > h) {
        c.why_not = "its lowest fold line is " + fmt(b - h, 3) +
                    " m below the hem (a_0 = " + fmt(b) + " m > h)";
        return out;
    }
    c.feasible = true;
    return out;
}

void set_smooth_sag(FoldSolution& s) {
    s.folds = 0;
    s.zmax_m = 0.0;
    s.amplitudes_m = {s.slack_amplitude_m};
}

}  // namespace

FoldSolution solve_folds(const ClothParams& p) {
    validate(p);
    FoldSolution s;
    s.stress_ratio = stress_ratio(p);
    const double span = p.support_span_m();
    s.slack_amplitude_m = top_edge_amplitude_m(span, p.width_m);
    const double top_residual =
        std::abs(top_edge_length_m(span, s.slack_amplitude_m) - p.width_m) / p.width_m;

    if (s.stress_ratio >= 1.0) {
        s.regime = FoldSolution::Regime::no_wrinkles;
        s.Q = 1.0;
        set_smooth_sag(s);
        s.residual = top_residual;
        s.explanation = "S = " + fmt(s.stress_ratio) +
                        " >= 1: the critical buckling stress exceeds the hanging stress, so the "
                        "cloth is too stiff to wrinkle and hangs as a smooth sag";
        return s;
    }
    s.Q = amplitude_ratio(s.stress_ratio);
    if (p.inset_m == 0.0) {
        s.regime = FoldSolution::Regime::no_feasible_folds;
        set_smooth_sag(s);
        s.residual = top_residual;
        s.explanation = "the supports are the full width apart (inset 0): the top edge is taut, "
                        "there is no slack to fold and the cloth hangs flat";
        return s;
    }

    std::vector<std::vector<double>> amplitudes;  // per candidate, when solved
    for (int n = 1; n <= kMaxFolds; ++n) {
        CandidateSolve c = solve_candidate(p, s.slack_amplitude_m, s.Q, n);
        s.candidates.push_back(c.candidate);
        amplitudes.push_back(std::move(c.amplitudes));
        if (c.candidate.feasible) s.feasible_folds.push_back(n);
        if (c.stop_scan) break;
    }
    // Rule: the lowest fold line nearest the hem.  That is the largest n with a_0 <= h;
    // if no n keeps a_0 <= h, the solved n with the smallest a_0 (just below the hem).
    int best = -1;
    for (std::size_t i = 0; i < s.candidates.size(); ++i)
        if (s.candidates[i].feasible) best = int(i);
    const bool below_hem = best < 0;
    if (below_hem)
        for (std::size_t i = 0; i < s.candidates.size(); ++i)
            if (s.candidates[i].solved &&
                (best < 0 || s.candidates[i].lowest_amplitude_m < s.candidates[std::size_t(best)].lowest_amplitude_m))
                best = int(i);
    if (best < 0) {
        s.regime = FoldSolution::Regime::no_feasible_folds;
        set_smooth_sag(s);
        s.residual = top_residual;
        const std::string reason = s.candidates.empty() ? std::string("no candidate")
                                                        : s.candidates.back().why_not;
        s.explanation = "S = " + fmt(s.stress_ratio) + " < 1 so the cloth would buckle, but no " +
                        "fold count n = 1.." + std::to_string(s.candidates.size()) +
                        " solves the length equations (n = " + std::to_string(s.candidates.size()) +
                        ": " + reason + "); it is drawn as a smooth sag";
        return s;
    }
    const FoldCandidate& chosen = s.candidates[std::size_t(best)];
    s.regime = FoldSolution::Regime::wrinkled;
    s.folds = chosen.folds;
    s.zmax_m = chosen.zmax_m;
    s.amplitudes_m = amplitudes[std::size_t(best)];
    s.residual = chosen.residual;
    if (below_hem)
        s.explanation = std::to_string(s.folds) + " folds: S = " + fmt(s.stress_ratio) +
                        " < 1 so the cloth buckles with Q = " + fmt(s.Q) +
                        "; no fold count keeps the lowest fold line above the hem (a_0 <= h), so "
                        "the one with the lowest fold line nearest the hem is used (" +
                        fmt(chosen.lowest_amplitude_m - p.height_m, 3) + " m below it)";
    else
        s.explanation = std::to_string(s.folds) + " folds: S = " + fmt(s.stress_ratio) +
                        " < 1 so the cloth buckles with Q = " + fmt(s.Q) + "; " +
                        std::to_string(s.feasible_folds.size()) +
                        " fold counts solve the length equations with a_0 <= h and the largest "
                        "(lowest fold line nearest the hem) is used";
    return s;
}

}  // namespace foldcast::drape
