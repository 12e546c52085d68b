#include "weighted_runs.hpp"

#include <algorithm>

#include "target_clones.hpp"

namespace foldcast::codec {

namespace {
constexpr std::int64_t kClamp = std::int64_t(1) << 40;

// A row run of one vertex, or a vertex-by-vertex one.
WeightedRun classify(const SpatialReference& s, const SpatialReference& s2, std::uint32_t v) {
    if (s.c < 0 || s2.c < 0) return {false, v, v + 1, {}};
    WeightedRun run{true, v, v + 1, {}};
    const std::int32_t taps[kSpatialTaps] = {s.a, s.b, s.c, s2.a, s2.b, s2.c};
    for (int i = 0; i < kSpatialTaps; ++i) run.offset[std::size_t(i)] = v - static_cast<std::uint32_t>(taps[i]);
    return run;
}

// Taps other than the vertex just before must lie before the run: it may grow while shorter
// than the nearest of them.
std::uint32_t longest_row(const WeightedRun& run) {
    std::uint32_t nearest = UINT32_MAX;
    for (std::uint32_t o : run.offset)
        if (o != 1) nearest = std::min(nearest, o);
    return nearest;
}
}  // namespace

WeightedPlan weighted_plan(const SpatialTaps& taps) {
    WeightedPlan plan;
    for (std::uint32_t v = 0; v < taps.first.size(); ++v) {
        const WeightedRun next = classify(taps.first[v], taps.second[v], v);
        if (!plan.runs.empty()) {
            WeightedRun& run = plan.runs.back();
            const bool extends =
                next.row == run.row && next.offset == run.offset && (!run.row || v - run.begin < longest_row(run));
            if (extends) {
                run.end = v + 1;
                continue;
            }
        }
        plan.runs.push_back(next);
    }
    return plan;
}

namespace {
// pre[k] = the sum of the taps behind the row, for every coordinate of the run (vectorised).
FOLDCAST_AVX2_CLONES
void row_sums(const WeightedRun& run, const SpatialWeights& w, const std::int64_t* r, std::int64_t* pre) {
    const std::size_t begin = 3 * std::size_t(run.begin), end = 3 * std::size_t(run.end);
    for (std::size_t k = begin; k < end; ++k) pre[k - begin] = 0;
    for (std::size_t i = 0; i < kSpatialTaps; ++i) {
        if (run.offset[i] == 1) continue;
        const std::int64_t weight = w[i];
        const std::int64_t* tap = r - 3 * std::size_t(run.offset[i]);
        for (std::size_t k = begin; k < end; ++k) pre[k - begin] += weight * tap[k];
    }
}

void row_run(const WeightedRun& run, const SpatialWeights& w, const std::int32_t* q, std::int64_t m, std::int64_t* r,
             std::vector<std::int64_t>& pre) {
    pre.resize(3 * std::size_t(run.end - run.begin));
    row_sums(run, w, r, pre.data());
    std::int64_t previous = 0;  // the weight of the vertex just before (several taps may be it)
    for (std::size_t i = 0; i < kSpatialTaps; ++i)
        if (run.offset[i] == 1) previous += w[i];
    constexpr std::int64_t kHalf = std::int64_t(1) << (kWeightShift - 1);
    const std::size_t begin = 3 * std::size_t(run.begin), end = 3 * std::size_t(run.end);
    std::int64_t x = r[begin - 3], y = r[begin - 2], z = r[begin - 1];
    for (std::size_t k = begin; k < end; k += 3) {
        const std::int64_t* p = &pre[k - begin];
        x = std::clamp(std::int64_t(q[k]) * m + ((p[0] + previous * x + kHalf) >> kWeightShift), -kClamp, kClamp);
        y = std::clamp(std::int64_t(q[k + 1]) * m + ((p[1] + previous * y + kHalf) >> kWeightShift), -kClamp, kClamp);
        z = std::clamp(std::int64_t(q[k + 2]) * m + ((p[2] + previous * z + kHalf) >> kWeightShift), -kClamp, kClamp);
        r[k] = x;
        r[k + 1] = y;
        r[k + 2] = z;
    }
}
}  // namespace

void weighted_residuals(const WeightedPlan& plan, const SpatialTaps& taps, const SpatialWeights& w,
                        const std::int32_t* q, std::int64_t m, std::int64_t* r, std::vector<std::int64_t>& scratch) {
    for (const WeightedRun& run : plan.runs) {
        if (run.row) {
            row_run(run, w, q, m, r, scratch);
            continue;
        }
        for (std::size_t v = run.begin; v < run.end; ++v)
            for (int c = 0; c < 3; ++c) {
                const std::size_t k = 3 * v + static_cast<std::size_t>(c);
                r[k] = std::clamp(std::int64_t(q[k]) * m + weighted_prediction(taps.first[v], taps.second[v], w, r, c),
                                  -kClamp, kClamp);
            }
    }
}

}  // namespace foldcast::codec
