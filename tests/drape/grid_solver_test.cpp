// The relaxation's global step by DCT (drape/relax/grid_solver.hpp) against a dense solve of
// the same system with the pinned vertices eliminated.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

#include "foldcast/core/error.hpp"
#include "grid_solver.hpp"

namespace foldcast::drape::detail {
namespace {

// (L + anchor I) over every vertex, L the warp/weft graph Laplacian of the grid.
Eigen::MatrixXd grid_matrix(GridSize grid, double anchor) {
    const int n = grid.nu * grid.nv;
    Eigen::MatrixXd a = anchor * Eigen::MatrixXd::Identity(n, n);
    const auto edge = [&](int i, int j) { a(i, i) += 1.0, a(j, j) += 1.0, a(i, j) -= 1.0, a(j, i) -= 1.0; };
    for (int v = 0; v < grid.nv; ++v)
        for (int u = 0; u < grid.nu; ++u) {
            const int k = v * grid.nu + u;
            if (u + 1 < grid.nu) edge(k, k + 1);
            if (v + 1 < grid.nv) edge(k, k + grid.nu);
        }
    return a;
}

// The reference: the free block solved densely, pins moved to the right-hand side.
Eigen::VectorXd dense_solve(GridSize grid, double anchor, const std::vector<int>& pinned, const Eigen::VectorXd& rhs,
                            const Eigen::VectorXd& values) {
    const int n = grid.nu * grid.nv;
    const Eigen::MatrixXd a = grid_matrix(grid, anchor);
    std::vector<int> index(std::size_t(n), 0), free;
    for (int p : pinned) index[std::size_t(p)] = -1;
    for (int k = 0; k < n; ++k)
        if (index[std::size_t(k)] == 0) free.push_back(k);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
    for (std::size_t i = 0; i < pinned.size(); ++i) x[pinned[i]] = values[Eigen::Index(i)];
    const Eigen::Index f = Eigen::Index(free.size());
    Eigen::MatrixXd aff(f, f);
    Eigen::VectorXd b(f);
    for (Eigen::Index r = 0; r < f; ++r) {
        b[r] = rhs[free[std::size_t(r)]];
        for (int p : pinned) b[r] -= a(free[std::size_t(r)], p) * x[p];
        for (Eigen::Index c = 0; c < f; ++c) aff(r, c) = a(free[std::size_t(r)], free[std::size_t(c)]);
    }
    const Eigen::VectorXd xf = aff.ldlt().solve(b);
    for (Eigen::Index r = 0; r < f; ++r) x[free[std::size_t(r)]] = xf[r];
    return x;
}

struct Case {
    GridSize grid;
    double anchor;
    std::vector<int> pinned;
};

TEST(GridSolver, MatchesADenseSolveWithThePinsEliminated) {
    const std::vector<Case> cases = {
        {{8, 8}, 0.1, {0, 7}},                           // two corner supports
        {{13, 9}, 0.05, {0, 6, 12}},                     // odd sizes, three supports along the top
        {{31, 25}, 0.2, {0, 10, 20, 30, 24 * 31 + 15}},  // a pin inside the grid
        {{5, 11}, 1.0, {}},                              // nothing pinned
    };
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (const Case& c : cases) {
        const int n = c.grid.nu * c.grid.nv;
        Eigen::VectorXd rhs(n), values(Eigen::Index(c.pinned.size()));
        for (int k = 0; k < n; ++k) rhs[k] = uniform(rng);
        for (Eigen::Index i = 0; i < values.size(); ++i) values[i] = uniform(rng);
        const GridSolver solver(c.grid, c.anchor, c.pinned);
        const Eigen::VectorXd x = solver.solve(rhs, values);
        const Eigen::VectorXd reference = dense_solve(c.grid, c.anchor, c.pinned, rhs, values);
        EXPECT_LT((x - reference).cwiseAbs().maxCoeff(), 1e-9 * (1.0 + reference.cwiseAbs().maxCoeff()))
            << c.grid.nu << "x" << c.grid.nv;
        for (std::size_t i = 0; i < c.pinned.size(); ++i)
            EXPECT_NEAR(x[c.pinned[i]], values[Eigen::Index(i)], 1e-12) << "pin " << i;
        // The free rows satisfy the system (pinned rows are replaced by the pins).
        const Eigen::VectorXd residual = grid_matrix(c.grid, c.anchor) * x - rhs;
        for (int k = 0; k < n; ++k) {
            if (std::find(c.pinned.begin(), c.pinned.end(), k) != c.pinned.end()) continue;
            EXPECT_NEAR(residual[k], 0.0, 1e-9) << k;
        }
    }
}

TEST(GridSolver, SameBytesFromAnyThread) {
    const GridSize grid{40, 30};
    const GridSolver solver(grid, 0.1, {0, 39});
    Eigen::VectorXd rhs(grid.nu * grid.nv), values(2);
    for (Eigen::Index k = 0; k < rhs.size(); ++k) rhs[k] = std::sin(0.37 * double(k));
    values << 0.25, -0.5;
    const Eigen::VectorXd here = solver.solve(rhs, values);
    std::vector<Eigen::VectorXd> there(4);
    std::vector<std::thread> threads;
    for (auto& out : there) threads.emplace_back([&] { out = solver.solve(rhs, values); });
    for (auto& t : threads) t.join();
    for (const auto& out : there) EXPECT_EQ(out, here);
}

TEST(GridSolver, RejectsBadInput) {
    EXPECT_THROW(GridSolver({4, 4}, 0.0, {0}), InputError);
    EXPECT_THROW(GridSolver({4, 4}, 0.1, {16}), InputError);
    const GridSolver solver({4, 4}, 0.1, {0});
    EXPECT_THROW(solver.solve(Eigen::VectorXd::Zero(15), Eigen::VectorXd::Zero(1)), InputError);
    EXPECT_THROW(solver.solve(Eigen::VectorXd::Zero(16), Eigen::VectorXd::Zero(2)), InputError);
}

}  // namespace
}  // namespace foldcast::drape::detail
