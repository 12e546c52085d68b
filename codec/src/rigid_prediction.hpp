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

struct RigidFrame {
    double u[3], w[3], n[3];  // orthonormal: along a->b, in the triangle's plane, normal
};

// False for a triangle too thin to give a direction (edges or area below a grid step).
inline bool rigid_frame(const double* a, const double* b, const double* c, RigidFrame& f) {
    const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double l1 = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    const double ln = std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    if (!(l1 >= 1.0) || !(ln >= l1)) return false;
    for (int k = 0; k < 3; ++k) {
        f.u[k] = e1[k] / l1;
        f.n[k] = cr[k] / ln;
    }
    f.w[0] = f.n[1] * f.u[2] - f.n[2] * f.u[1];
    f.w[1] = f.n[2] * f.u[0] - f.n[0] * f.u[2];
    f.w[2] = f.n[0] * f.u[1] - f.n[1] * f.u[0];
    return true;
}

// Writes the predicted grid coordinates of v into out[3]; false (out untouched) where the
// triangle is degenerate in either frame, and the caller falls back to the parallelogram.
// P and D are the 3N-coordinate rows of the temporal prediction and of the decoded frame.
template <typename P, typename D>
inline bool rigid_prediction(const SpatialReference& s, std::size_t v, const P* predicted, const D* decoded,
                             std::int64_t* out) {
    if (s.c < 0) return false;
    double pa[3], pb[3], pc[3], da[3], db[3], dc[3], d[3];
    const auto ia = 3 * static_cast<std::size_t>(s.a), ib = 3 * static_cast<std::size_t>(s.b),
               ic = 3 * static_cast<std::size_t>(s.c);
    for (int k = 0; k < 3; ++k) {
        pa[k] = double(predicted[ia + k]);
        pb[k] = double(predicted[ib + k]);
        pc[k] = double(predicted[ic + k]);
        da[k] = double(decoded[ia + k]);
        db[k] = double(decoded[ib + k]);
        dc[k] = double(decoded[ic + k]);
        d[k] = double(predicted[3 * v + k]) - pa[k];
    }
    RigidFrame from, to;
    if (!rigid_frame(pa, pb, pc, from) || !rigid_frame(da, db, dc, to)) return false;
    const double x = from.u[0] * d[0] + from.u[1] * d[1] + from.u[2] * d[2];
    const double y = from.w[0] * d[0] + from.w[1] * d[1] + from.w[2] * d[2];
    const double z = from.n[0] * d[0] + from.n[1] * d[1] + from.n[2] * d[2];
    for (int k = 0; k < 3; ++k) {
        const double p = da[k] + (x * to.u[k] + y * to.w[k] + z * to.n[k]);
        out[k] = static_cast<std::int64_t>(std::floor(p + 0.5));
    }
    return true;
}

}  // namespace foldcast::codec
