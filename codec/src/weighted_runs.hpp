#pragma once
// The decoder's plan for a frame with weights of its own (spatial_weights.hpp), vertex order
// kept, as spatial_runs.hpp plans the parallelogram's: on a regular grid the six taps of
// nearly every vertex sit at the same offsets behind it and only one, the vertex just
// before, lies in its own row.  A run's other taps are summed in a vectorised pass over
// rows finished before it; what is left is a short recurrence along the row.  Vertices
// without such a pattern go one by one through weighted_prediction().
#include <array>
#include <cstdint>
#include <vector>

#include "predictive_profile.hpp"
#include "spatial_weights.hpp"

namespace foldcast::codec {

struct WeightedRun {
    bool row = false;                                  // else vertex by vertex
    std::uint32_t begin = 0, end = 0;                  // vertices [begin, end)
    std::array<std::uint32_t, kSpatialTaps> offset{};  // row runs: tap i is vertex v - offset[i]
};

struct WeightedPlan {
    std::vector<WeightedRun> runs;  // covering every vertex in order
};
WeightedPlan weighted_plan(const SpatialTaps& taps);

// A frame's residuals r (3 per vertex) from its quantised values q, step m and weights w:
// r_v = q_v m + weighted_prediction(...).  Every r is clamped to +-2^40, far beyond any
// valid residual (|r| < 2^32), so corrupt weights cannot make the sums overflow.  `scratch`
// is reused from frame to frame.
void weighted_residuals(const WeightedPlan& plan, const SpatialTaps& taps, const SpatialWeights& w,
                        const std::int32_t* q, std::int64_t m, std::int64_t* r, std::vector<std::int64_t>& scratch);

}  // namespace foldcast::codec
