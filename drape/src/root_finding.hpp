#pragma once
// Safeguarded Newton iteration on a bracket: Newton steps while they stay inside the bracket
// and shrink it fast enough, bisection otherwise.  Used by the fold solver's 1-D problems.
#include <algorithm>
#include <cmath>
#include <limits>

namespace foldcast::drape::detail {

struct Root {
    double x = 0.0;
    double f = 0.0;
};

// f_and_df(x, f, df) evaluates f and f'.  Needs f(lo) and f(hi) of opposite signs (or zero).
// Stops when |f| <= f_tol or the bracket is down to a few ulps.
template <typename F>
Root newton_bracketed(F&& f_and_df, double lo, double hi, double f_tol, int max_iterations = 200) {
    double flo, dlo, fhi, dhi;
    f_and_df(lo, flo, dlo);
    f_and_df(hi, fhi, dhi);
    if (std::abs(flo) <= f_tol) return {lo, flo};
    if (std::abs(fhi) <= f_tol) return {hi, fhi};
    const bool rising = flo < 0.0;  // orientation: f(lo) < 0 < f(hi) or the reverse
    double x = std::abs(flo) < std::abs(fhi) ? lo : hi;
    double fx = x == lo ? flo : fhi;
    double dfx = x == lo ? dlo : dhi;
    bool slow = false;
    for (int it = 1; it <= max_iterations; ++it) {
        double next = dfx != 0.0 ? x - fx / dfx : lo - 1.0;
        // Bisect when Newton leaves the bracket or its last step did not halve |f|.
        if (!(next > lo && next < hi) || slow) next = 0.5 * (lo + hi);
        const double previous_abs_f = std::abs(fx);
        x = next;
        f_and_df(x, fx, dfx);
        slow = std::abs(fx) > 0.5 * previous_abs_f;
        if (std::abs(fx) <= f_tol) return {x, fx};
        if ((fx < 0.0) == rising)
            lo = x;
        else
            hi = x;
        if (hi - lo <= 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(lo), std::abs(hi)))
            return {x, fx};
    }
    return {x, fx};
}

}  // namespace foldcast::drape::detail
