// The top edge y = A cos(pi x / l) between the supports and its length, in closed form:
// with theta = pi x / l and k = pi A / l,
//   length = (l/pi) int_{-pi/2}^{pi/2} sqrt(1 + k^2 sin^2 theta) dtheta
//          = (2 l / pi) sqrt(1 + k^2) E(m),   m = k^2 / (1 + k^2),
// E the complete elliptic integral of the second kind (std::comp_ellint_2 takes sqrt(m)).
#include <cmath>

#include "foldcast/drape/drape.hpp"
#include "root_finding.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::drape {

namespace {

// Length and its derivative with respect to A.
void length_and_slope(double span_m, double amplitude_m, double& length, double& slope) {
    const double k = kPi * amplitude_m / span_m;
    const double k2 = k * k;
    const double root = std::sqrt(1.0 + k2);
    const double modulus = k / root;
    const double e = std::comp_ellint_2(modulus);
    length = 2.0 * span_m / kPi * root * e;
    // d/dk (2l/pi) int sqrt(1 + k^2 s^2) = (1/k) [length - (2l/pi) int 1/sqrt(1 + k^2 s^2)],
    // and int_0^{pi/2} 1/sqrt(1 + k^2 sin^2) = K(m) / sqrt(1 + k^2).
    if (k < 1e-4) {
        slope = kPi / span_m * (span_m / 2.0) * k;  // series: length ~ l (1 + k^2/4)
    } else {
        const double kk = std::comp_ellint_1(modulus);
        slope = kPi / span_m * (length - 2.0 * span_m / kPi * kk / root) / k;
    }
}
}  // namespace

double top_edge_length_m(double span_m, double amplitude_m) {
    double length, slope;
    length_and_slope(span_m, amplitude_m, length, slope);
    return length;
}

double top_edge_amplitude_m(double span_m, double length_m) {
    if (length_m <= span_m) return 0.0;
    // The curve is at least as long as its vertical travel 2A and at most l + 2A, so A lies in
    // [(L - l)/2, L/2]; the length grows monotonically with A.
    const auto f = [&](double a, double& f_value, double& df) {
        length_and_slope(span_m, a, f_value, df);
        f_value -= length_m;
    };
    const double tol = 1e-14 * length_m;
    return detail::newton_bracketed(f, 0.5 * (length_m - span_m), 0.5 * length_m, tol).x;
}

}  // namespace foldcast::drape
