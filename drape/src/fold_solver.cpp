// The tension-field fold solve (docs/drape.md, "The model") with the hem closure (docs/drape.md):
// Q from the critical-stress equation, then for each fold count n one configuration fixed
// by the top edge and the hem keeping their length, and n chosen as the most folds whose
// zig-zag fits the centre fibre.
//
// Top edge: y = a_n cos, z = zmax cos has amplitude A = sqrt(a_n^2 + zmax^2), and its length
// equation fixes A alone (top_edge_amplitude_m).  With b = a_0 the one unknown
// (a_i = b Q^-i, zmax^2 = A^2 - b^2 Q^-2n), the centre fibre's zig-zag through the n folds
// has length Z(b) = sum_{i=1..n} sqrt((b Q^-i)^2 + 4 zmax^2).  The original model set
// Z = h; here the fibre may end its zig-zag above the hem and hang straight for the rest
// (Z <= h), which leaves one free parameter per n.  It is fixed by the hem keeping its
// length: every fibre at x hangs c = cos(pi x/l) times the centre's zig-zag, then straight,
// so the hem is the curve y = -h + c (Z - a_0), z = c zmax, as long as the top edge exactly
// when Z - a_0 = a_n.  So g(b) = Z(b) - b (1 + Q^-n) = 0: g(0) = 2 n A > 0 and, where zmax
// reaches 0 (b = A Q^n), g = -2A < 0; the root is bracketed and unique (checked numerically
// over Q in 1.001-10, n < 40, Q^n <= 1e8) and found by safeguarded Newton.
// Rule for n: the largest n with Z <= h (the most folds the cloth's height holds).  Z at the
// root grows with n, so the scan stops at the first n whose zig-zag is longer than h.
#include <algorithm>
#include <cmath>

#include "foldcast/core/error.hpp"
#include "foldcast/drape/drape.hpp"
#include "fold_geometry.hpp"
#include "paper_closure.hpp"
#include "root_finding.hpp"

namespace foldcast::drape {

namespace {

// More folds than this are below any useful grid resolution; the scan stops there.
constexpr int kMaxFolds = 1000;
constexpr double kRootTolerance = 1e-13;  // |g| / h at which a root is accepted

// Z(b) and dZ/db for one fold count, and the shape for a given b.
class ZigZag {
public:
    ZigZag(double slack_amplitude_m, double q, int folds) : a_(slack_amplitude_m), q_(q), folds_(folds) {
        const double log_q = std::log(q);
        inv_q_n_ = std::exp(-folds * log_q);
        r2_.resize(static_cast<std::size_t>(folds));
        for (int i = 1; i <= folds; ++i) {
            const double r = (q - 1.0) * std::exp(-i * log_q);  // (a_{i-1} - a_i) / a_0
            r2_[static_cast<std::size_t>(i - 1)] = r * r;
        }
    }

    double inv_q_n() const { return inv_q_n_; }
    // b = A Q^n makes zmax = 0; fold lines 100 h below the support line are no answer either
    // (the cap keeps Q^n finite).
    double b_limit(double height_m) const {
        const double log_limit = std::log(a_) - std::log(inv_q_n_);
        return log_limit >= std::log(100.0 * height_m) ? 100.0 * height_m : std::exp(log_limit);
    }

    void length(double b, double& z, double& dz_db) const {
        const double z2 = std::max(0.0, a_ * a_ - b * b * inv_q_n_ * inv_q_n_);  // zmax^2
        const double c_z = -4.0 * inv_q_n_ * inv_q_n_;
        z = 0.0;
        dz_db = 0.0;
        for (double r2 : r2_) {
            const double term = std::sqrt(b * b * r2 + 4.0 * z2);
            z += term;
            if (term > 0.0) dz_db += b * (r2 + c_z) / term;
        }
    }

    // Amplitudes a_0..a_n and zmax for a_0 = b.
    void shape(double b, std::vector<double>& amplitudes, double& zmax) const {
        amplitudes.resize(static_cast<std::size_t>(folds_) + 1);
        for (int i = 0; i <= folds_; ++i) amplitudes[static_cast<std::size_t>(i)] = b * std::pow(q_, -i);
        const double an = b * inv_q_n_;
        zmax = std::sqrt(std::max(0.0, a_ * a_ - an * an));
    }

private:
    double a_, q_;
    int folds_;
    double inv_q_n_ = 1.0;
    std::vector<double> r2_;
};

// Relative residuals of the two length equations, recomputed from the final a_i and zmax:
// the top edge and the hem (y = -h + c (Z - a_0), z = c zmax) both as long as L.
double residual(const ClothParams& p, const std::vector<double>& amplitudes, double zmax) {
    const double l = p.support_span_m();
    const double top = std::abs(top_edge_length_m(l, std::hypot(amplitudes.back(), zmax)) - p.width_m);
    const double hem_lift = detail::zig_zag_length_m(amplitudes, zmax) - amplitudes.front();
    const double hem = std::abs(top_edge_length_m(l, std::hypot(hem_lift, zmax)) - p.width_m);
    return std::max(top, hem) / p.width_m;
}

struct CandidateSolve {
    FoldCandidate candidate;
    std::vector<double> amplitudes;
    bool stop_scan = false;  // no larger n can fit
};

CandidateSolve solve_candidate(const ClothParams& p, double slack_a, double q, int n) {
    CandidateSolve out;
    FoldCandidate& c = out.candidate;
    c.folds = n;
    const double h = p.height_m;
    const ZigZag zig(slack_a, q, n);
    const double hem_slope = 1.0 + zig.inv_q_n();  // d(a_0 + a_n)/db
    const auto g = [&](double b, double& value, double& slope) {
        double z, dz;
        zig.length(b, z, dz);
        value = z - hem_slope * b;
        slope = dz - hem_slope;
    };
    const double b_hi = zig.b_limit(h);
    double g_hi, slope;
    g(b_hi, g_hi, slope);
    if (g_hi > 0.0) {  // only where the cap bites: the zig-zag would be longer than 100 h
        c.why_not = "its fold lines would hang more than " + detail::format_number(100.0 * h) + " m low: too many folds";
        out.stop_scan = true;
        return out;
    }
    const double b = detail::newton_bracketed(g, 0.0, b_hi, kRootTolerance * h).x;
    double zmax;
    zig.shape(b, out.amplitudes, zmax);
    if (!(b > 0.0) || !(zmax > 0.0)) {  // not reached for A > 0 (g(0) > 0 > g(b_hi))
        c.why_not = "the hem closure has no root with a_0 > 0 and zmax > 0";
        out.stop_scan = true;
        return out;
    }
    c.solved = true;
    c.lowest_amplitude_m = out.amplitudes.front();
    c.top_amplitude_m = out.amplitudes.back();
    c.zmax_m = zmax;
    c.fold_length_m = detail::zig_zag_length_m(out.amplitudes, zmax);
    c.residual = residual(p, out.amplitudes, zmax);
    if (c.fold_length_m > h) {
        c.why_not =
            "its zig-zag (" + detail::format_number(c.fold_length_m) + " m) is longer than the height " + detail::format_number(h) + " m: too many folds";
        out.stop_scan = true;
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

const char* closure_name(Closure closure) { return closure == Closure::paper ? "paper" : "hem"; }

bool closure_from_name(const std::string& name, Closure& closure) {
    if (name == "hem") closure = Closure::hem;
    else if (name == "paper") closure = Closure::paper;
    else return false;
    return true;
}

FoldSolution solve_folds(const ClothParams& params) {
    validate(params);
    const ClothParams p = bay_params(params);  // every bay folds alike
    FoldSolution s;
    s.closure = p.closure;
    s.stress_ratio = stress_ratio(p);
    const double span = p.support_span_m();
    s.slack_amplitude_m = top_edge_amplitude_m(span, p.width_m);
    const double top_residual = std::abs(top_edge_length_m(span, s.slack_amplitude_m) - p.width_m) / p.width_m;

    if (s.stress_ratio >= 1.0) {
        s.regime = FoldSolution::Regime::no_wrinkles;
        s.Q = 1.0;
        set_smooth_sag(s);
        s.residual = top_residual;
        s.explanation = "S = " + detail::format_number(s.stress_ratio) +
                        " >= 1: the critical buckling stress exceeds the hanging stress, so the "
                        "cloth is too stiff to wrinkle and hangs as a smooth sag";
        return s;
    }
    s.Q = s.critical_Q = amplitude_ratio(s.stress_ratio);
    if (p.inset_m == 0.0) {
        s.regime = FoldSolution::Regime::no_feasible_folds;
        set_smooth_sag(s);
        s.residual = top_residual;
        s.explanation =
            "the supports are the full width apart (inset 0): the top edge is taut, "
            "there is no slack to fold and the cloth hangs flat";
        return s;
    }
    if (p.closure == Closure::paper) return detail::solve_paper_closure(p, std::move(s));

    std::vector<std::vector<double>> amplitudes;  // per candidate, when solved
    for (int n = 1; n <= kMaxFolds; ++n) {
        CandidateSolve c = solve_candidate(p, s.slack_amplitude_m, s.Q, n);
        s.candidates.push_back(c.candidate);
        amplitudes.push_back(std::move(c.amplitudes));
        if (c.candidate.feasible) s.feasible_folds.push_back(n);
        if (c.stop_scan) break;
    }
    // Rule: the most folds whose zig-zag fits the centre fibre.  When even one fold is longer
    // than the cloth, S < 1 still buckles the top: one fold, cut by the hem.
    const bool cut = s.feasible_folds.empty();
    const std::size_t best = cut ? 0 : std::size_t(s.feasible_folds.back() - 1);
    const FoldCandidate& chosen = s.candidates.at(best);
    s.regime = FoldSolution::Regime::wrinkled;
    s.folds = chosen.folds;
    s.zmax_m = chosen.zmax_m;
    s.fold_length_m = chosen.fold_length_m;
    s.amplitudes_m = amplitudes[best];
    s.residual = chosen.residual;
    const std::string head = std::to_string(s.folds) + (s.folds == 1 ? " fold" : " folds") +
                             ": S = " + detail::format_number(s.stress_ratio) + " < 1 so the cloth buckles with Q = " + detail::format_number(s.Q) + "; ";
    if (cut)
        s.explanation = head + "even one fold's zig-zag (" + detail::format_number(s.fold_length_m) + " m) is longer than the height " +
                        detail::format_number(p.height_m) + " m, so the hem cuts across it";
    else
        s.explanation = head + "the most folds whose zig-zag (" + detail::format_number(s.fold_length_m) + " m) fits the height " +
                        detail::format_number(p.height_m) + " m; the rest of the centre fibre hangs straight below the lowest fold line";
    return s;
}

}  // namespace foldcast::drape
