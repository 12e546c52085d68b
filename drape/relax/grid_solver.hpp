#pragma once
// The relaxation's global step: (L + anchor I) x = b on an nu x nv grid, L the graph
// Laplacian of the warp/weft edges (every edge weight 1, free edges), with some vertices
// pinned to given positions.  L + anchor I is diagonal in the 2-D DCT-II basis, so a solve is
// a forward and an inverse DCT (dct.hpp) instead of a sparse Cholesky factor's two triangular
// solves; the pins are met by the capacitance-matrix method (a k x k system for k pins).
#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "foldcast/drape/drape.hpp"

namespace foldcast::drape::detail {

class GridSolver {
public:
    // anchor > 0 (the plain Laplacian of a free grid is singular); pinned: distinct vertices.
    GridSolver(GridSize grid, double anchor, std::vector<int> pinned);
    ~GridSolver();
    GridSolver(const GridSolver&) = delete;
    GridSolver& operator=(const GridSolver&) = delete;

    // rhs: one entry per vertex (those of pinned vertices are ignored); pinned_values: one
    // per pinned vertex, in the constructor's order.  Returns x with (L + anchor I) x = rhs on
    // every free vertex and x = pinned_values on the pinned ones (to rounding).  Safe to call
    // from several threads at once; the result does not depend on the thread.
    Eigen::VectorXd solve(const Eigen::VectorXd& rhs, const Eigen::VectorXd& pinned_values) const;
    // The same into x (one entry per vertex, not rhs's memory): no allocation.
    void solve(const Eigen::VectorXd& rhs, const Eigen::VectorXd& pinned_values, Eigen::Ref<Eigen::VectorXd> x) const;
    // The same on arrays (rhs, x and spectrum, the DCT's work array: one entry per vertex
    // each, three separate arrays).  T: double, or float (the transforms' arithmetic is double
    // either way; the relaxation's iterations then move half the memory, and the pins are met
    // to float's rounding).
    template <typename T>
    void solve(const T* rhs, const Eigen::VectorXd& pinned_values, T* x, T* spectrum) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace foldcast::drape::detail
