#pragma once
// Small pieces of the fold model shared by the closures and the garment surface.
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace foldcast::drape::detail {

// Z: the centre fibre's zig-zag through the fold lines a_0..a_n, each fold a straight chord
// from one line to the next across the fold's depth 2 zmax.
inline double zig_zag_length_m(const std::vector<double>& amplitudes_m, double zmax_m) {
    double z = 0.0;
    for (std::size_t i = 1; i < amplitudes_m.size(); ++i)
        z += std::hypot(amplitudes_m[i - 1] - amplitudes_m[i], 2.0 * zmax_m);
    return z;
}

// A value for the explanations users read: `precision` significant digits.
inline std::string format_number(double v, int precision = 4) {
    std::ostringstream s;
    s.precision(precision);
    s << v;
    return s.str();
}

}  // namespace foldcast::drape::detail
