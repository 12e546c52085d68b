#include "spatial_runs.hpp"
#include "target_clones.hpp"

#include <algorithm>

namespace foldcast::codec {

namespace {
SpatialRun classify(const SpatialReference& s, std::uint32_t v) {
    using Kind = SpatialRun::Kind;
    const auto previous = static_cast<std::int32_t>(v) - 1;
    if (s.a < 0) return {Kind::none, v, v + 1};
    if (s.c < 0) return {s.a == previous ? Kind::chain : Kind::gather, v, v + 1};
    if (s.a != previous && s.b != previous) return {Kind::gather, v, v + 1};
    const std::int32_t other = s.a == previous ? s.b : s.a;
    return {Kind::row, v, v + 1, v - static_cast<std::uint32_t>(other), v - static_cast<std::uint32_t>(s.c)};
}

std::vector<SpatialRun> spatial_runs(const std::vector<SpatialReference>& refs) {
    std::vector<SpatialRun> runs;
    for (std::uint32_t v = 0; v < refs.size(); ++v) {
        const SpatialRun next = classify(refs[v], v);
        if (!runs.empty()) {
            SpatialRun& run = runs.back();
            // A row run may only read rows finished before it starts.
            const bool extends = next.kind == run.kind && next.up == run.up && next.corner == run.corner &&
                                 (run.kind != SpatialRun::Kind::row || v < run.begin + std::min(run.up, run.corner));
            if (extends) {
                run.end = v + 1;
                continue;
            }
        }
        runs.push_back(next);
    }
    return runs;
}
}  // namespace

SpatialPlan spatial_plan(const std::vector<SpatialReference>& refs) {
    SpatialPlan plan{spatial_runs(refs), std::vector<std::array<std::uint32_t, 3>>(refs.size())};
    // N <= 2^28 (a reader's limit, docs/fca-format.md): offsets up to 3 N fit 32 bits.
    const auto offset = [zero = static_cast<std::uint32_t>(3 * refs.size())](std::int32_t u) {
        return u < 0 ? zero : 3 * static_cast<std::uint32_t>(u);
    };
    for (std::size_t v = 0; v < refs.size(); ++v) {
        const SpatialReference& s = refs[v];
        // spatial_prediction(): nothing without a; only r_a without c.
        const bool parallelogram = s.a >= 0 && s.c >= 0;
        plan.gather[v] = {offset(s.a), offset(parallelogram ? s.b : -1), offset(parallelogram ? s.c : -1)};
    }
    return plan;
}

namespace {
void run_residuals(const SpatialRun& run, const std::vector<std::array<std::uint32_t, 3>>& gather,
                   const std::uint32_t* q, std::uint32_t m, std::uint32_t* r) {
    const std::size_t begin = 3 * std::size_t(run.begin), end = 3 * std::size_t(run.end);
    switch (run.kind) {
        case SpatialRun::Kind::none:
            for (std::size_t k = begin; k < end; ++k) r[k] = q[k] * m;
            return;
        case SpatialRun::Kind::gather:
            for (std::size_t v = run.begin; v < run.end; ++v) {
                const auto [a, b, c] = gather[v];
                for (std::size_t k = 0; k < 3; ++k) r[3 * v + k] = q[3 * v + k] * m + r[a + k] + r[b + k] - r[c + k];
            }
            return;
        case SpatialRun::Kind::row: {
            // r_v = r_{v-1} + (q_v m + r_{v-up} - r_{v-corner}): the bracket reads only vertices
            // before the run (vectorised), then a running sum along the run.
            const std::size_t up = 3 * std::size_t(run.up), corner = 3 * std::size_t(run.corner);
            for (std::size_t k = begin; k < end; ++k) r[k] = q[k] * m + r[k - up] - r[k - corner];
            std::uint32_t x = r[begin - 3], y = r[begin - 2], z = r[begin - 1];
            for (std::size_t k = begin; k < end; k += 3) {
                r[k] = x += r[k];
                r[k + 1] = y += r[k + 1];
                r[k + 2] = z += r[k + 2];
            }
            return;
        }
        case SpatialRun::Kind::chain: {
            std::uint32_t x = r[begin - 3], y = r[begin - 2], z = r[begin - 1];
            for (std::size_t k = begin; k < end; k += 3) {
                r[k] = x += q[k] * m;
                r[k + 1] = y += q[k + 1] * m;
                r[k + 2] = z += q[k + 2] * m;
            }
            return;
        }
    }
}
}  // namespace

FOLDCAST_AVX2_CLONES
void spatial_residuals(const SpatialPlan& plan, const std::uint32_t* q, std::uint32_t m, std::uint32_t* r) {
    for (const SpatialRun& run : plan.runs) run_residuals(run, plan.gather, q, m, r);
}

}  // namespace foldcast::codec
