#pragma once
// Profile `motion` (docs/codec.md): the spatial prediction that carries a vertex along with
// the rigid motion of its neighbourhood.  The parallelogram rule of the default profile
// predicts the temporal residual r_v = r_a + r_b - r_c, exact when the frame moved affinely
// and the reference quad (a, b, c, v) is flat; a folded garment turning with a body is
// neither.  Here the rotation that takes the triangle (a, b, c) of the temporal prediction P
// to its decoded position D in this frame is applied to v's offset from a:
//   prediction(v) = D_a + R (P_v - P_a),
// exact for any rigid motion of the neighbourhood however curved it is.  Encoder and
// decoder both call it, in IEEE double with the operations in one fixed order and no
// fused multiply-add (the codec and its WebAssembly build compile with -ffp-contract=off,
// and no caller has an FMA target clone), then round, so they agree bit for bit on every
// machine.
#include <cmath>
#include <cstdint>

#include "predictive_profile.hpp"

namespace foldcast::codec {

// A triangle (a, b, c) as the rigid transport reads it: e1 = b - a, the normal cr = e1 x
// (c - a), w = cr x e1 (in the plane, across e1), and the lengths of e1 and cr.  Unit
// vectors are never formed: the transport divides once per axis by the product of both
// frames' lengths, which keeps two square roots and three divisions on the decoder's
// vertex-to-vertex dependency chain instead of twelve operations of that cost.
struct RigidFrame {
    double e1[3], cr[3], w[3], l1, ln;
};

inline void cross(const double* a, const double* b, double* out) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}
inline double dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// False for a triangle too thin to give a direction (edge or area below a grid step).
template <typename G>
inline bool rigid_frame(const G* grid, std::size_t ia, std::size_t ib, std::size_t ic, RigidFrame& f) {
    double e2[3];
    for (std::size_t k = 0; k < 3; ++k) {
        f.e1[k] = double(grid[ib + k]) - double(grid[ia + k]);
        e2[k] = double(grid[ic + k]) - double(grid[ia + k]);
    }
    cross(f.e1, e2, f.cr);
    cross(f.cr, f.e1, f.w);
    f.l1 = std::sqrt(dot(f.e1, f.e1));
    f.ln = std::sqrt(dot(f.cr, f.cr));
    return f.l1 >= 1.0 && f.ln >= f.l1;
}

// floor(p + 0.5) without a libm call (x86-64's baseline has no rounding instruction), for
// |p| < 2^62: truncation, then one step down where it rounded a negative value up.
inline std::int64_t round_half_up(double p) {
    const double r = p + 0.5;
    if (!(r > -0x1p62 && r < 0x1p62)) return r > 0 ? std::int64_t(1) << 62 : -(std::int64_t(1) << 62);
    const auto i = static_cast<std::int64_t>(r);
    return double(i) > r ? i - 1 : i;
}

// Writes the predicted grid coordinates of v into out[3]; false (out untouched) where v has
// no triangle or it is degenerate in either frame, and the caller falls back to the
// parallelogram.  P and D are the 3N-coordinate rows of the temporal prediction and of the
// decoded frame (D read only at a, b, c).
template <typename P, typename D>
inline bool rigid_prediction(const SpatialReference& s, std::size_t v, const P* predicted, const D* decoded,
                             std::int64_t* out) {
    if (s.c < 0) return false;
    const auto ia = 3 * static_cast<std::size_t>(s.a), ib = 3 * static_cast<std::size_t>(s.b),
               ic = 3 * static_cast<std::size_t>(s.c);
    RigidFrame from, to;
    if (!rigid_frame(predicted, ia, ib, ic, from) || !rigid_frame(decoded, ia, ib, ic, to)) return false;
    double d[3];
    for (std::size_t k = 0; k < 3; ++k) d[k] = double(predicted[3 * v + k]) - double(predicted[ia + k]);
    // v's offset from a in the frame (e1, w, cr) of P, in units that the same axes of D
    // turn back into grid steps.
    const double sx = dot(from.e1, d) / (from.l1 * to.l1);
    const double sy = dot(from.w, d) / ((from.ln * from.l1) * (to.ln * to.l1));
    const double sz = dot(from.cr, d) / (from.ln * to.ln);
    for (std::size_t k = 0; k < 3; ++k) {
        const double p = double(decoded[ia + k]) + (sx * to.e1[k] + sy * to.w[k] + sz * to.cr[k]);
        out[k] = round_half_up(p);
    }
    return true;
}

}  // namespace foldcast::codec
