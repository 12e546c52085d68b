#include "isometric_prediction.hpp"

#include <cmath>

namespace foldcast::codec {
namespace {

double dot(const double* x, const double* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; }

// A NaN-safe clamp to [-kIsometricClamp, kIsometricClamp], then the nearest integer (halves
// upwards).  Truncation, corrected for negative values, instead of std::floor: the
// baseline x86-64 target has no rounding instruction, and a call per coordinate showed.
std::int64_t to_integer(double x) {
    if (!(x > -kIsometricClamp)) return -static_cast<std::int64_t>(kIsometricClamp);
    if (!(x < kIsometricClamp)) return static_cast<std::int64_t>(kIsometricClamp);
    const double y = x + 0.5;
    const auto t = static_cast<std::int64_t>(y);  // towards zero
    return t - (static_cast<double>(t) > y);
}

}  // namespace

bool isometric_frame(const IsometricInputs& in, IsometricFrame& out) {
    double p0[3], xa[3], xb[3], da[3], db[3];
    for (int c = 0; c < 3; ++c) {
        p0[c] = double(in.p0[c]);
        xa[c] = double(in.xa[c]);
        xb[c] = double(in.xb[c]);
        da[c] = double(in.lv[c] - in.la[c]);
        db[c] = double(in.lv[c] - in.lb[c]);
    }
    const double la2 = dot(da, da), lb2 = dot(db, db);
    const double d[3] = {xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2]};
    const double d2 = dot(d, d);
    if (!(d2 >= 1.0)) return false;  // a and b on one grid point
    const double inverse = 1.0 / std::sqrt(d2);
    const double u[3] = {d[0] * inverse, d[1] * inverse, d[2] * inverse};
    // The circle: centre on the axis `along` from a, radius `radius`; two spheres that do not
    // meet give the point of the axis between them (radius 0).
    const double along = (la2 - lb2 + d2) * (0.5 * inverse);
    const double h2 = la2 - along * along;
    const double radius = h2 > 0.0 ? std::sqrt(h2) : 0.0;
    const double centre[3] = {xa[0] + along * u[0], xa[1] + along * u[1], xa[2] + along * u[2]};
    double w[3] = {p0[0] - centre[0], p0[1] - centre[1], p0[2] - centre[2]};
    const double wu = dot(w, u);
    for (int c = 0; c < 3; ++c) w[c] -= wu * u[c];
    const double w2 = dot(w, w);
    if (!(w2 >= 1e-6)) return false;  // p0 on the axis: every point of the circle is as near
    const double w_inverse = 1.0 / std::sqrt(w2);
    for (double& x : w) x *= w_inverse;
    const double t[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    for (int c = 0; c < 3; ++c) {
        out.origin[c] = centre[c] + radius * w[c];
        out.axis[0][c] = t[c];
        out.axis[1][c] = w[c];
        out.axis[2][c] = u[c];
    }
    return true;
}

void isometric_quantise(const IsometricFrame& frame, const std::int32_t target[3], std::int64_t s, std::int64_t q[3]) {
    const double e[3] = {double(target[0]) - frame.origin[0], double(target[1]) - frame.origin[1],
                         double(target[2]) - frame.origin[2]};
    const double inverse = 1.0 / double(s);
    for (int j = 0; j < 3; ++j) q[j] = to_integer(dot(e, frame.axis[j]) * inverse);
}

void isometric_reconstruct(const IsometricFrame& frame, const std::int64_t q[3], std::int64_t s, std::int64_t out[3]) {
    for (int c = 0; c < 3; ++c) {
        double x = frame.origin[c];
        for (int j = 0; j < 3; ++j) x += double(q[j] * s) * frame.axis[j][c];
        out[c] = to_integer(x);
    }
}

}  // namespace foldcast::codec
