// The grid's global step by DCT (grid_solver.hpp).  The path graph's Laplacian on n vertices
// (free ends) has the DCT-II vectors cos(pi k (i + 1/2) / n) as eigenvectors with eigenvalues
// 2 - 2 cos(pi k / n); the grid's is their Kronecker sum.  A DCT-II (REDFT10) followed by a
// DCT-III (REDFT01) multiplies by 2n per dimension; both come from dct.hpp (FFTW real FFTs,
// FFTW_ESTIMATE plans: the same algorithm on every run, the same bytes).
#include "grid_solver.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "dct.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::drape::detail {

struct GridSolver::Impl {
    GridSize grid;
    std::size_t n = 0;
    std::vector<int> pinned;
    Eigen::VectorXd inverse_eigenvalues;  // 1 / (eigenvalue x 4 nu nv), per DCT mode, as GridDct lays them out
    Eigen::VectorXf inverse_eigenvalues_f;
    std::unique_ptr<GridDct> dct;
    Eigen::MatrixXd response;  // (L + anchor I)^-1 at every vertex to a unit load on each pin
    Eigen::MatrixXf response_f;  // the same in float, for the float solve
    Eigen::LDLT<Eigen::MatrixXd> capacitance;

    // y = (L + anchor I)^-1 b, pins ignored; with zero_pins, b's entries on the pins are taken
    // as 0 (b itself is left as it is).  The forward DCT reads b where it can (no copy when
    // the pins' entries are +0 already, or there are none to zero); the inverse DCT scales by
    // the inverse eigenvalues as it reads.  spectrum: n values, neither b's nor y's memory.
    template <typename T>
    void free_solve(const T* b, T* y, T* spectrum, const T* inverse, bool zero_pins) const {
        bool copy = false;
        if (zero_pins)
            for (int p : pinned) copy = copy || b[p] != T(0) || std::signbit(b[p]);
        const T* in = b;
        if (copy) {
            std::copy(b, b + n, y);
            for (int p : pinned) y[p] = T(0);
            in = y;
        }
        dct->forward(in, spectrum);
        dct->inverse(spectrum, y, inverse);
    }
    void free_solve(const Eigen::VectorXd& b, Eigen::Ref<Eigen::VectorXd> y, bool zero_pins = false) const {
        Eigen::VectorXd spectrum(static_cast<Eigen::Index>(n));
        free_solve(b.data(), y.data(), spectrum.data(), inverse_eigenvalues.data(), zero_pins);
    }
};

GridSolver::GridSolver(GridSize grid, double anchor, std::vector<int> pinned) : impl_(std::make_unique<Impl>()) {
    if (!(anchor > 0.0)) throw InputError("grid solver: the anchor must be positive");
    Impl& m = *impl_;
    m.grid = grid;
    m.n = std::size_t(grid.nu) * std::size_t(grid.nv);
    for (int p : pinned)
        if (p < 0 || std::size_t(p) >= m.n)
            throw InputError("pinned vertex " + std::to_string(p) + " is not in the grid");
    m.pinned = std::move(pinned);
    m.inverse_eigenvalues.resize(Eigen::Index(m.n));
    const double scale = 4.0 * grid.nu * grid.nv;
    for (int q = 0; q < grid.nv; ++q)
        for (int p = 0; p < grid.nu; ++p) {
            const double eigenvalue =
                anchor + (2.0 - 2.0 * std::cos(kPi * p / grid.nu)) + (2.0 - 2.0 * std::cos(kPi * q / grid.nv));
            m.inverse_eigenvalues[p * grid.nv + q] = 1.0 / (eigenvalue * scale);
        }
    m.dct = std::make_unique<GridDct>(grid);
    // Capacitance matrix: the pins' displacement under a unit load on each pin.
    const Eigen::Index k = Eigen::Index(m.pinned.size());
    m.response.resize(Eigen::Index(m.n), k);
    for (Eigen::Index j = 0; j < k; ++j) {
        Eigen::VectorXd load = Eigen::VectorXd::Zero(Eigen::Index(m.n));
        load[m.pinned[std::size_t(j)]] = 1.0;
        m.free_solve(load, m.response.col(j));
    }
    m.response_f = m.response.cast<float>();
    m.inverse_eigenvalues_f = m.inverse_eigenvalues.cast<float>();
    Eigen::MatrixXd c(k, k);
    for (Eigen::Index i = 0; i < k; ++i) c.row(i) = m.response.row(m.pinned[std::size_t(i)]);
    m.capacitance.compute(c);
}

GridSolver::~GridSolver() = default;

Eigen::VectorXd GridSolver::solve(const Eigen::VectorXd& rhs, const Eigen::VectorXd& pinned_values) const {
    Eigen::VectorXd x(rhs.size());
    solve(rhs, pinned_values, x);
    return x;
}

void GridSolver::solve(const Eigen::VectorXd& rhs, const Eigen::VectorXd& pinned_values,
                       Eigen::Ref<Eigen::VectorXd> x) const {
    const Impl& m = *impl_;
    if (std::size_t(rhs.size()) != m.n || std::size_t(x.size()) != m.n ||
        std::size_t(pinned_values.size()) != m.pinned.size())
        throw InputError("grid solver: one right-hand side per vertex and one value per pin");
    Eigen::VectorXd spectrum(static_cast<Eigen::Index>(m.n));
    solve(rhs.data(), pinned_values, x.data(), spectrum.data());
}

template <typename T>
void GridSolver::solve(const T* rhs, const Eigen::VectorXd& pinned_values, T* x, T* spectrum) const {
    const Impl& m = *impl_;
    if (std::size_t(pinned_values.size()) != m.pinned.size()) throw InputError("grid solver: one value per pin");
    constexpr bool kDouble = std::is_same_v<T, double>;
    if constexpr (kDouble)
        m.free_solve(rhs, x, spectrum, m.inverse_eigenvalues.data(), true);
    else
        m.free_solve(rhs, x, spectrum, m.inverse_eigenvalues_f.data(), true);
    if (m.pinned.empty()) return;
    // Loads mu on the pins such that the pins sit at their values: C mu = values - x_pins.
    Eigen::VectorXd gap(pinned_values.size());
    for (std::size_t i = 0; i < m.pinned.size(); ++i)
        gap[Eigen::Index(i)] = pinned_values[Eigen::Index(i)] - double(x[m.pinned[i]]);
    // One pass over x (in float, its rounding is float's, as x's).
    const Eigen::VectorXd loads = m.capacitance.solve(gap);
    Eigen::Map<Eigen::Matrix<T, Eigen::Dynamic, 1>> solved(x, Eigen::Index(m.n));
    if constexpr (kDouble)
        solved.noalias() += m.response * loads;
    else
        solved.noalias() += m.response_f * loads.cast<float>();
}

template void GridSolver::solve(const double*, const Eigen::VectorXd&, double*, double*) const;
template void GridSolver::solve(const float*, const Eigen::VectorXd&, float*, float*) const;

}  // namespace foldcast::drape::detail
