#pragma once
// The directions of a grid's warp and weft edges, each blended with its two neighbours along
// the same thread: what the relaxation's smoothing phase projects the edges onto, so that a
// thread that must lengthen does so by bending smoothly instead of kinking at every vertex
// (docs/drape.md, "Thread smoothing").
#include <array>
#include <vector>

#include "foldcast/drape/drape.hpp"

namespace foldcast::drape::detail {

// T: double or float, as the positions.
template <typename T>
struct ThreadDirections {
    // Per vertex k, coordinate c: the unit direction of the edge k -> k + 1 (right) and of
    // k -> k + nu (down); entries without such an edge are 0.
    std::array<std::vector<T>, 3> right, down;
    std::array<std::vector<T>, 3> raw_right, raw_down;  // each edge's own: the blend's input
};

// Positions coordinate by coordinate (x[k], y[k], z[k], k = row * nu + column).  Each edge's
// unit direction d is replaced by (d + w (d_before + d_after)) / |...| where the thread has an
// edge on both sides (end edges keep their own: a one-sided blend would bend the thread's end
// towards its neighbour); w = `weight`.  On a circular arc the blend is the edge's own
// direction, so smoothing leaves even bending alone and removes alternating kinks.  Each
// entry depends only on the input, so the result is the same for any thread count.  `out`
// keeps its storage between calls; reuse it for one grid size only (its zeros are set when
// the storage is new).  Computed in T, a row at a time in SIMD packets (the animation's
// frames, in float, paid 6 % of their CPU for this in double, one edge at a time).
template <typename T>
void thread_directions(const T* x, const T* y, const T* z, GridSize grid, double weight, ThreadDirections<T>& out);

}  // namespace foldcast::drape::detail
