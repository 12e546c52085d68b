// The decoder's run plan for spatially predicted residuals (codec/src/spatial_runs.*) and
// the int32 cubic temporal prediction: both must give exactly what the encoder's
// per-vertex, int64 arithmetic gives.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "predictive_profile.hpp"
#include "spatial_runs.hpp"
#include "test_animations.hpp"

namespace foldcast::codec {
namespace {

// What the encoder computes, vertex by vertex in int64: r_v = q_v m + r_a + r_b - r_c.
std::vector<std::int64_t> reference_residuals(const std::vector<SpatialReference>& refs,
                                              const std::vector<std::int32_t>& q, std::int64_t m) {
    std::vector<std::int64_t> r(q.size());
    for (std::size_t v = 0; v < refs.size(); ++v)
        for (int c = 0; c < 3; ++c) {
            const std::size_t k = 3 * v + static_cast<std::size_t>(c);
            r[k] = q[k] * m + spatial_prediction(refs[v], r.data(), c);
        }
    return r;
}

void expect_runs_match_reference(const std::vector<Triangle>& triangles, std::size_t n) {
    const std::vector<SpatialReference> refs = spatial_references(n, triangles);
    const SpatialPlan plan = spatial_plan(refs);
    const std::vector<SpatialRun>& runs = plan.runs;
    // The runs cover every vertex once, in order, and a row run reads only earlier vertices.
    std::uint32_t next = 0;
    for (const SpatialRun& run : runs) {
        ASSERT_EQ(run.begin, next);
        ASSERT_LT(run.begin, run.end);
        if (run.kind == SpatialRun::Kind::row) {
            EXPECT_LE(run.end, run.begin + std::min(run.up, run.corner));
        }
        next = run.end;
    }
    ASSERT_EQ(next, n);

    std::mt19937 rng(7);
    std::uniform_int_distribution<std::int32_t> small(-3, 3);
    std::vector<std::int32_t> q(3 * n);
    for (auto& v : q) v = small(rng);
    q[3 * (n / 2)] = 400000;  // an escape-sized value too
    for (std::uint32_t m : {1u, 32u, 1000u}) {
        const std::vector<std::int64_t> expected = reference_residuals(refs, q, m);
        std::vector<std::uint32_t> r(3 * n + 3, 0xdeadbeef);
        std::fill(r.end() - 3, r.end(), 0u);
        spatial_residuals(plan, reinterpret_cast<const std::uint32_t*>(q.data()), m, r.data());
        EXPECT_EQ(r[3 * n] | r[3 * n + 1] | r[3 * n + 2], 0u) << "the zeros after the frame stay zero";
        for (std::size_t k = 0; k < 3 * n; ++k)
            ASSERT_EQ(static_cast<std::int32_t>(r[k]), expected[k]) << "coordinate " << k << ", m " << m;
    }
}

TEST(SpatialRuns, RegularGridIsMostlyRowRunsAndMatchesTheEncoder) {
    const Animation grid = test::wave_grid(17, 9, 1);
    const std::vector<SpatialRun> runs =
        spatial_plan(spatial_references(grid.vertex_count(), grid.topology.triangles)).runs;
    std::size_t in_rows = 0;
    for (const SpatialRun& run : runs)
        if (run.kind == SpatialRun::Kind::row) in_rows += run.end - run.begin;
    EXPECT_GE(in_rows, std::size_t(16 * 8)) << "every vertex off the first row and column";
    expect_runs_match_reference(grid.topology.triangles, grid.vertex_count());
}

TEST(SpatialRuns, ShuffledGridAndBlenderMeshMatchTheEncoder) {
    const Animation grid = test::wave_grid(13, 11, 1);
    // The same grid with its vertices renumbered at random: mostly gathers.
    std::vector<std::uint32_t> order(grid.vertex_count());
    std::iota(order.begin(), order.end(), 0u);
    std::shuffle(order.begin(), order.end(), std::mt19937(3));
    std::vector<Triangle> shuffled;
    for (const Triangle& t : grid.topology.triangles) shuffled.push_back({order[t[0]], order[t[1]], order[t[2]]});
    expect_runs_match_reference(shuffled, grid.vertex_count());
    const Animation cloth = test::basic_cloth();
    expect_runs_match_reference(cloth.topology.triangles, cloth.vertex_count());
}

TEST(CubicPrediction, Int32AndInt64ArithmeticAgreeWithinTheBound) {
    const std::size_t row = 3000;
    const PredictiveLayout layout(33, 4);
    std::size_t t = 0;
    while (layout.references[t].kind != TemporalReference::Kind::cubic) ++t;
    std::mt19937 rng(11);
    for (const std::int64_t largest : {std::int64_t(1000), std::int64_t(100'000'000)}) {
        ASSERT_TRUE(cubic_fits_int32(largest));
        std::uniform_int_distribution<std::int32_t> value(-1024, static_cast<std::int32_t>(largest));
        std::vector<std::vector<std::int32_t>> frames(33, std::vector<std::int32_t>(row));
        std::vector<const std::int32_t*> pointers;
        for (auto& f : frames) {
            for (auto& v : f) v = value(rng);
            pointers.push_back(f.data());
        }
        std::vector<std::int32_t> narrow(row), wide(row);
        predict_frame(layout.references[t], TemporalMode::layout, t, pointers.data(), row, largest, narrow.data());
        predict_frame(layout.references[t], TemporalMode::layout, t, pointers.data(), row, std::int64_t(1) << 30,
                      wide.data());
        EXPECT_EQ(narrow, wide) << "largest " << largest;
    }
    EXPECT_FALSE(cubic_fits_int32(std::int64_t(1) << 27));
}

}  // namespace
}  // namespace foldcast::codec
