#pragma once
// The decoder's plan for the spatial prediction of a frame's residuals (r_v = q_v m +
// r_a + r_b - r_c, predictive_profile.hpp), vertex order kept: runs of consecutive vertices
// predicted alike.  On a regular grid nearly every vertex is a `row` vertex, predicted from
// the one before it, the one a row up and a corner, so a run's brackets depend only on
// earlier rows (a vectorised pass) and the rest is a running sum along the row.  Other
// meshes fall back to per-vertex gathers.
#include <array>
#include <cstdint>
#include <vector>

#include "predictive_profile.hpp"

namespace foldcast::codec {

struct SpatialRun {
    enum class Kind {
        none,    // no prediction: r_v = q_v m
        chain,   // r_v = q_v m + r_{v-1}
        row,     // r_v = q_v m + r_{v-1} + r_{v-up} - r_{v-corner}, v - up and v - corner before the run
        gather,  // anything else, vertex by vertex from the references
    } kind = Kind::none;
    std::uint32_t begin = 0, end = 0;  // vertices [begin, end)
    std::uint32_t up = 0, corner = 0;  // row runs only
};

struct SpatialPlan {
    std::vector<SpatialRun> runs;  // covering [0, refs.size()) in order
    // Per vertex, the offsets of r_a, r_b and r_c for a gather: 3 a, 3 b, 3 c, a missing
    // reference 3 n, three zeros after the frame's residuals, so gathers need no branch.
    std::vector<std::array<std::uint32_t, 3>> gather;
};
SpatialPlan spatial_plan(const std::vector<SpatialReference>& refs);

// A frame's residuals r (3 n values, then three zeros the caller keeps) from its quantised
// values q and step m, run by run.  Unsigned arithmetic wraps modulo 2^32: for a valid file
// every true value fits int32, so the result is exact, and corrupt values cannot overflow
// (the caller range-checks).
void spatial_residuals(const SpatialPlan& plan, const std::uint32_t* q, std::uint32_t m, std::uint32_t* r);

}  // namespace foldcast::codec
