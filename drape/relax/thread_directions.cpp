#include "thread_directions.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/Core>
#include <cmath>

namespace foldcast::drape::detail {
namespace {

template <typename T>
using Line = Eigen::Map<Eigen::Array<T, Eigen::Dynamic, 1>>;
template <typename T>
using ConstLine = Eigen::Map<const Eigen::Array<T, Eigen::Dynamic, 1>>;

// Unit directions of the `count` edges from p[.][first + e] to p[.][first + e + step] into
// out[.][first + e] (0 for a zero-length edge): (d0 d0 + d1 d1) + d2 d2 and d / length, the
// operations of one edge at a time, so double's result is unchanged by the packets.
template <typename T>
void unit_edges(const T* const p[3], std::size_t first, std::size_t count, std::size_t step,
                std::array<std::vector<T>, 3>& out) {
    for (std::size_t c = 0; c < 3; ++c)
        Line<T>(out[c].data() + first, Eigen::Index(count)) =
            ConstLine<T>(p[c] + first + step, Eigen::Index(count)) - ConstLine<T>(p[c] + first, Eigen::Index(count));
    Line<T> dx(out[0].data() + first, Eigen::Index(count)), dy(out[1].data() + first, Eigen::Index(count)),
        dz(out[2].data() + first, Eigen::Index(count));
    const Eigen::Array<T, Eigen::Dynamic, 1> length = (dx.square() + dy.square() + dz.square()).sqrt();
    const auto positive = length > T(0);
    for (Line<T>* d : {&dx, &dy, &dz}) *d = positive.select(*d / length, T(0));
}

// out[.][first + e] = normalised raw[.][k] + w (raw[.][k - step] + raw[.][k + step]), k =
// first + e, for `count` entries.
template <typename T>
void blend(const std::array<std::vector<T>, 3>& raw, std::size_t first, std::size_t count, std::size_t step, T w,
           std::array<std::vector<T>, 3>& out) {
    const auto at = [&](std::size_t c, std::size_t from) {
        return ConstLine<T>(raw[c].data() + from, Eigen::Index(count));
    };
    for (std::size_t c = 0; c < 3; ++c)
        Line<T>(out[c].data() + first, Eigen::Index(count)) =
            at(c, first) + w * (at(c, first - step) + at(c, first + step));
    Line<T> dx(out[0].data() + first, Eigen::Index(count)), dy(out[1].data() + first, Eigen::Index(count)),
        dz(out[2].data() + first, Eigen::Index(count));
    const Eigen::Array<T, Eigen::Dynamic, 1> squared = dx.square() + dy.square() + dz.square();
    const Eigen::Array<T, Eigen::Dynamic, 1> inverse = (squared > T(0)).select(T(1) / squared.sqrt(), T(0));
    for (Line<T>* d : {&dx, &dy, &dz}) *d *= inverse;
}

template <typename T>
void copy(const std::array<std::vector<T>, 3>& from, std::size_t k, std::array<std::vector<T>, 3>& to) {
    for (std::size_t c = 0; c < 3; ++c) to[c][k] = from[c][k];
}

}  // namespace

template <typename T>
void thread_directions(const T* x, const T* y, const T* z, GridSize grid, double weight, ThreadDirections<T>& out) {
    const std::size_t nu = std::size_t(grid.nu), nv = std::size_t(grid.nv), n = nu * nv;
    const T* const p[3] = {x, y, z};
    // The raw directions first (every one is read by its neighbours' blends), then the blend.
    // Every entry with an edge is written below, so zeros (the entries without) are only set
    // when the storage is new.
    for (std::size_t c = 0; c < 3; ++c)
        for (auto* v : {&out.raw_right[c], &out.raw_down[c], &out.right[c], &out.down[c]})
            if (v->size() != n) v->assign(n, T(0));
    tbb::parallel_for(std::size_t(0), nv, [&](std::size_t j) {
        const std::size_t row = j * nu;
        unit_edges(p, row, nu - 1, 1, out.raw_right);
        if (j + 1 < nv) unit_edges(p, row, nu, nu, out.raw_down);
    });
    const T w = T(weight);
    tbb::parallel_for(std::size_t(0), nv, [&](std::size_t j) {
        const std::size_t row = j * nu;
        // Along the row: the first and last edges keep their own, the rest are blended.
        if (weight > 0.0 && nu >= 4) {
            copy(out.raw_right, row, out.right);
            blend(out.raw_right, row + 1, nu - 3, 1, w, out.right);
            copy(out.raw_right, row + nu - 2, out.right);
        } else {
            for (std::size_t i = 0; i + 1 < nu; ++i) copy(out.raw_right, row + i, out.right);
        }
        // Down the columns: the first and last rows of edges keep their own.
        if (j + 1 < nv) {
            if (weight > 0.0 && j > 0 && j + 2 < nv)
                blend(out.raw_down, row, nu, nu, w, out.down);
            else
                for (std::size_t i = 0; i < nu; ++i) copy(out.raw_down, row + i, out.down);
        }
    });
}

template void thread_directions(const double*, const double*, const double*, GridSize, double,
                                ThreadDirections<double>&);
template void thread_directions(const float*, const float*, const float*, GridSize, double, ThreadDirections<float>&);

}  // namespace foldcast::drape::detail
