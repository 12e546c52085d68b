// The grid's global step by DCT (grid_solver.hpp).  The path graph's Laplacian on n vertices
// (free ends) has the DCT-II vectors cos(pi k (i + 1/2) / n) as eigenvectors with eigenvalues
// 2 - 2 cos(pi k / n); the grid's is their Kronecker sum.  FFTW's REDFT10 (DCT-II) followed by
// REDFT01 (DCT-III) multiplies by 2n per dimension.  Plans are made once with FFTW_ESTIMATE
// (the same algorithm on every run: the same bytes) under a lock (FFTW's planner is not
// thread-safe; executing a plan on other arrays is).
#include "grid_solver.hpp"

#include <fftw3.h>

#include <cmath>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

#include "foldcast/core/error.hpp"

namespace foldcast::drape::detail {
namespace {

std::mutex& planner_lock() {
    static std::mutex lock;
    return lock;
}

struct FftwBuffer {
    double* data;
    explicit FftwBuffer(std::size_t n) : data(fftw_alloc_real(n)) {
        if (!data) throw std::bad_alloc();
    }
    ~FftwBuffer() { fftw_free(data); }
    FftwBuffer(const FftwBuffer&) = delete;
    FftwBuffer& operator=(const FftwBuffer&) = delete;
};

}  // namespace

struct GridSolver::Impl {
    GridSize grid;
    std::size_t n = 0;
    std::vector<int> pinned;
    Eigen::VectorXd inverse_eigenvalues;  // 1 / (eigenvalue x 4 nu nv), per DCT mode
    fftw_plan forward = nullptr, inverse = nullptr;
    Eigen::MatrixXd response;  // (L + anchor I)^-1 at every vertex to a unit load on each pin
    Eigen::LDLT<Eigen::MatrixXd> capacitance;

    // y = (L + anchor I)^-1 b, pins ignored; with zero_pins, b's entries on the pins are taken
    // as 0 (without a copy of b).
    Eigen::VectorXd free_solve(const Eigen::VectorXd& b, bool zero_pins = false) const {
        // Per-thread scratch kept between calls: the relaxation solves every iteration, and
        // fresh half-megabyte buffers each time cost more in malloc than in the DCT.
        struct Scratch {
            std::size_t size = 0;
            std::unique_ptr<FftwBuffer> a, c;
        };
        thread_local Scratch scratch;
        if (scratch.size != n) {
            scratch.a = std::make_unique<FftwBuffer>(n), scratch.c = std::make_unique<FftwBuffer>(n);
            scratch.size = n;
        }
        FftwBuffer &a = *scratch.a, &c = *scratch.c;
        for (std::size_t k = 0; k < n; ++k) a.data[k] = b[Eigen::Index(k)];
        if (zero_pins)
            for (int p : pinned) a.data[p] = 0.0;
        fftw_execute_r2r(forward, a.data, c.data);
        for (std::size_t k = 0; k < n; ++k) c.data[k] *= inverse_eigenvalues[Eigen::Index(k)];
        fftw_execute_r2r(inverse, c.data, a.data);
        Eigen::VectorXd y(static_cast<Eigen::Index>(n));
        for (std::size_t k = 0; k < n; ++k) y[Eigen::Index(k)] = a.data[k];
        return y;
    }

    ~Impl() {
        const std::lock_guard<std::mutex> hold(planner_lock());
        if (forward) fftw_destroy_plan(forward);
        if (inverse) fftw_destroy_plan(inverse);
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
                anchor + (2.0 - 2.0 * std::cos(M_PI * p / grid.nu)) + (2.0 - 2.0 * std::cos(M_PI * q / grid.nv));
            m.inverse_eigenvalues[q * grid.nu + p] = 1.0 / (eigenvalue * scale);
        }
    {
        FftwBuffer a(m.n), b(m.n);
        const std::lock_guard<std::mutex> hold(planner_lock());
        // Rows of nu vertices, nv of them: the slow dimension first.
        m.forward = fftw_plan_r2r_2d(grid.nv, grid.nu, a.data, b.data, FFTW_REDFT10, FFTW_REDFT10, FFTW_ESTIMATE);
        m.inverse = fftw_plan_r2r_2d(grid.nv, grid.nu, b.data, a.data, FFTW_REDFT01, FFTW_REDFT01, FFTW_ESTIMATE);
    }
    if (!m.forward || !m.inverse) throw std::runtime_error("grid solver: FFTW could not plan the DCT");
    // Capacitance matrix: the pins' displacement under a unit load on each pin.
    const Eigen::Index k = Eigen::Index(m.pinned.size());
    m.response.resize(Eigen::Index(m.n), k);
    for (Eigen::Index j = 0; j < k; ++j) {
        Eigen::VectorXd load = Eigen::VectorXd::Zero(Eigen::Index(m.n));
        load[m.pinned[std::size_t(j)]] = 1.0;
        m.response.col(j) = m.free_solve(load);
    }
    Eigen::MatrixXd c(k, k);
    for (Eigen::Index i = 0; i < k; ++i) c.row(i) = m.response.row(m.pinned[std::size_t(i)]);
    m.capacitance.compute(c);
}

GridSolver::~GridSolver() = default;

Eigen::VectorXd GridSolver::solve(const Eigen::VectorXd& rhs, const Eigen::VectorXd& pinned_values) const {
    const Impl& m = *impl_;
    if (std::size_t(rhs.size()) != m.n || std::size_t(pinned_values.size()) != m.pinned.size())
        throw InputError("grid solver: one right-hand side per vertex and one value per pin");
    Eigen::VectorXd x = m.free_solve(rhs, true);
    if (m.pinned.empty()) return x;
    // Loads mu on the pins such that the pins sit at their values: C mu = values - x_pins.
    Eigen::VectorXd gap(pinned_values.size());
    for (std::size_t i = 0; i < m.pinned.size(); ++i)
        gap[Eigen::Index(i)] = pinned_values[Eigen::Index(i)] - x[m.pinned[i]];
    x += m.response * m.capacitance.solve(gap);
    return x;
}

}  // namespace foldcast::drape::detail
