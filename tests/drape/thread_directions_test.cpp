// The relaxation's smoothed thread directions (drape/relax/thread_directions.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "thread_directions.hpp"

namespace foldcast::drape::detail {
namespace {

struct Grid {
    GridSize size;
    std::vector<double> x, y, z;
    explicit Grid(GridSize s) : size(s), x(std::size_t(s.nu * s.nv)), y(x.size()), z(x.size()) {}
    void set(int i, int j, double px, double py, double pz) {
        const std::size_t k = std::size_t(j * size.nu + i);
        x[k] = px, y[k] = py, z[k] = pz;
    }
};

double dot_down(const ThreadDirections<double>& d, std::size_t k, const double v[3]) {
    return d.down[0][k] * v[0] + d.down[1][k] * v[1] + d.down[2][k] * v[2];
}

// Every column a circular arc in (y, z), every row straight along x: the blend of an arc's
// edges is the edge's own direction, and a straight thread stays straight.
TEST(ThreadDirections, EvenBendingIsLeftAlone) {
    Grid g({5, 12});
    const double radius = 0.3, step = 0.15;  // radians per edge
    for (int j = 0; j < 12; ++j)
        for (int i = 0; i < 5; ++i) g.set(i, j, 0.02 * i, -radius * std::sin(step * j), radius * (1 - std::cos(step * j)));
    ThreadDirections<double> d;
    thread_directions(g.x.data(), g.y.data(), g.z.data(), g.size, 0.5, d);
    for (std::size_t k = 0; k < g.x.size(); ++k) {
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(d.down[std::size_t(c)][k], d.raw_down[std::size_t(c)][k], 1e-12) << k;
            EXPECT_NEAR(d.right[std::size_t(c)][k], d.raw_right[std::size_t(c)][k], 1e-12) << k;
        }
    }
    EXPECT_NEAR(d.right[0][0], 1.0, 1e-12);
    EXPECT_EQ(d.right[0][4], 0.0);  // no edge to the right of the last column
}

// A column that zig-zags in z at every vertex: the blended directions point much nearer the
// thread's mean direction (straight down) than its edges do, except at the thread's two ends.
TEST(ThreadDirections, KinksAreSmoothedButEndsKeepTheirOwn) {
    Grid g({3, 10});
    for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 3; ++i) g.set(i, j, 0.01 * i, -0.01 * j, (j % 2) * 0.006);
    ThreadDirections<double> d;
    thread_directions(g.x.data(), g.y.data(), g.z.data(), g.size, 0.5, d);
    const double down[3] = {0.0, -1.0, 0.0};
    for (int j = 0; j + 1 < 10; ++j) {
        const std::size_t k = std::size_t(j * 3 + 1);
        const double raw = d.raw_down[0][k] * down[0] + d.raw_down[1][k] * down[1] + d.raw_down[2][k] * down[2];
        const double blended = dot_down(d, k, down);
        EXPECT_NEAR(d.down[0][k] * d.down[0][k] + d.down[1][k] * d.down[1][k] + d.down[2][k] * d.down[2][k], 1.0, 1e-12);
        if (j == 0 || j + 2 == 10)
            EXPECT_EQ(blended, raw) << "end edge " << j;
        else
            EXPECT_GT(blended, raw + 0.05) << "edge " << j;  // raw 0.857, blended ~0.99
    }
}

TEST(ThreadDirections, WeightZeroIsTheRawDirections) {
    Grid g({4, 4});
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) g.set(i, j, 0.01 * i + 0.001 * j * j, -0.01 * j, 0.002 * i * j);
    ThreadDirections<double> d;
    thread_directions(g.x.data(), g.y.data(), g.z.data(), g.size, 0.0, d);
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(d.down[std::size_t(c)], d.raw_down[std::size_t(c)]);
        EXPECT_EQ(d.right[std::size_t(c)], d.raw_right[std::size_t(c)]);
    }
}

}  // namespace
}  // namespace foldcast::drape::detail
