#include "thread_directions.hpp"

#include <tbb/parallel_for.h>

#include <cmath>

namespace foldcast::drape::detail {
namespace {

// Unit direction of p[b] - p[a] into out[.][a] (0 for a zero-length edge).
template <typename T>
void unit_edge(const T* const p[3], std::size_t a, std::size_t b, std::array<std::vector<double>, 3>& out) {
    const double d[3] = {double(p[0][b]) - double(p[0][a]), double(p[1][b]) - double(p[1][a]),
                         double(p[2][b]) - double(p[2][a])};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int c = 0; c < 3; ++c) out[std::size_t(c)][a] = len > 0.0 ? d[c] / len : 0.0;
}

// out[.][k] = normalised raw[.][k] + w (raw[.][k - step] + raw[.][k + step]).
void blend(const std::array<std::vector<double>, 3>& raw, std::size_t k, std::size_t step, double w,
           std::array<std::vector<double>, 3>& out) {
    double d[3], len2 = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
        d[c] = raw[c][k] + w * (raw[c][k - step] + raw[c][k + step]);
        len2 += d[c] * d[c];
    }
    const double inv = len2 > 0.0 ? 1.0 / std::sqrt(len2) : 0.0;
    for (std::size_t c = 0; c < 3; ++c) out[c][k] = d[c] * inv;
}

}  // namespace

template <typename T>
void thread_directions(const T* x, const T* y, const T* z, GridSize grid, double weight, ThreadDirections& out) {
    const std::size_t nu = std::size_t(grid.nu), nv = std::size_t(grid.nv), n = nu * nv;
    const T* const p[3] = {x, y, z};
    // The raw directions first (every one is read by its neighbours' blends), then the blend.
    // Every entry with an edge is written below, so zeros (the entries without) are only set
    // when the storage is new.
    for (std::size_t c = 0; c < 3; ++c)
        for (auto* v : {&out.raw_right[c], &out.raw_down[c], &out.right[c], &out.down[c]})
            if (v->size() != n) v->assign(n, 0.0);
    tbb::parallel_for(std::size_t(0), nv, [&](std::size_t j) {
        for (std::size_t i = 0; i < nu; ++i) {
            const std::size_t k = j * nu + i;
            if (i + 1 < nu) unit_edge(p, k, k + 1, out.raw_right);
            if (j + 1 < nv) unit_edge(p, k, k + nu, out.raw_down);
        }
    });
    tbb::parallel_for(std::size_t(0), nv, [&](std::size_t j) {
        for (std::size_t i = 0; i < nu; ++i) {
            const std::size_t k = j * nu + i;
            if (i + 1 < nu) {
                if (weight > 0.0 && i > 0 && i + 2 < nu)
                    blend(out.raw_right, k, 1, weight, out.right);
                else
                    for (std::size_t c = 0; c < 3; ++c) out.right[c][k] = out.raw_right[c][k];
            }
            if (j + 1 < nv) {
                if (weight > 0.0 && j > 0 && j + 2 < nv)
                    blend(out.raw_down, k, nu, weight, out.down);
                else
                    for (std::size_t c = 0; c < 3; ++c) out.down[c][k] = out.raw_down[c][k];
            }
        }
    });
}

template void thread_directions(const double*, const double*, const double*, GridSize, double, ThreadDirections&);
template void thread_directions(const float*, const float*, const float*, GridSize, double, ThreadDirections&);

}  // namespace foldcast::drape::detail
