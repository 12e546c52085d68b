#include "spatial_runs.hpp"

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
}  // namespace

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

namespace {
void run_residuals(const SpatialRun& run, const std::vector<SpatialReference>& refs, const std::uint32_t* q, std::uint32_t m,
                   std::uint32_t* r) {
    const std::size_t begin = 3 * std::size_t(run.begin), end = 3 * std::size_t(run.end);
    switch (run.kind) {
    case SpatialRun::Kind::none:
        for (std::size_t k = begin; k < end; ++k) r[k] = q[k] * m;
        return;
    case SpatialRun::Kind::gather:
        for (std::size_t v = run.begin; v < run.end; ++v) {
            const SpatialReference& s = refs[v];
            for (std::size_t c = 0; c < 3; ++c) {
                std::uint32_t p = s.a < 0 ? 0 : r[3 * std::size_t(s.a) + c];
                if (s.c >= 0) p += r[3 * std::size_t(s.b) + c] - r[3 * std::size_t(s.c) + c];
                r[3 * v + c] = q[3 * v + c] * m + p;
            }
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

void spatial_residuals(const std::vector<SpatialRun>& runs, const std::vector<SpatialReference>& refs, const std::uint32_t* q,
                       std::uint32_t m, std::uint32_t* r) {
    for (const SpatialRun& run : runs) run_residuals(run, refs, q, m, r);
}

}  // namespace foldcast::codec
