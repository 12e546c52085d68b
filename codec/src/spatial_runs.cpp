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

}  // namespace foldcast::codec
