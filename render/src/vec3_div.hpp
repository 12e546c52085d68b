#pragma once
// A 3-vector divided by a scalar, and normalised, with the three quotients in one SSE2
// division: Eigen divides a Vector3f component by component (three divss), and the path
// tracer's per-vertex normals, half vectors and light directions waited on those.  The same
// IEEE quotients, so the same floats.
#include <Eigen/Core>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace foldcast::render {

inline Eigen::Vector3f div3(const Eigen::Vector3f& v, float s) {
#if defined(__SSE2__)
    alignas(16) float q[4];
    _mm_store_ps(q, _mm_div_ps(_mm_setr_ps(v.x(), v.y(), v.z(), 0.0f), _mm_set1_ps(s)));
    return {q[0], q[1], q[2]};
#else
    return v / s;
#endif
}

// Eigen's normalized(): v / |v|, or v itself when |v| is 0.
inline Eigen::Vector3f normalized3(const Eigen::Vector3f& v) {
    const float n2 = v.squaredNorm();
    return n2 > 0.0f ? div3(v, std::sqrt(n2)) : v;
}

// normalized3 of two vectors at once: both square roots in one SSE2 instruction and the two
// divisions independent of each other, so the second does not wait for the first's chain
// (the hit's geometric and shading normals).  The same floats as two normalized3 calls.
inline void normalize_pair(Eigen::Vector3f& a, Eigen::Vector3f& b) {
#if defined(__SSE2__)
    const float a2 = a.squaredNorm(), b2 = b.squaredNorm();
    alignas(16) float roots[4];
    _mm_store_ps(roots, _mm_sqrt_ps(_mm_setr_ps(a2, b2, 1.0f, 1.0f)));
    if (a2 > 0.0f) a = div3(a, roots[0]);
    if (b2 > 0.0f) b = div3(b, roots[1]);
#else
    a = normalized3(a);
    b = normalized3(b);
#endif
}

}  // namespace foldcast::render
