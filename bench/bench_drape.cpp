// drape throughput: one fold solve, one garment grid (with and without its relaxation),
// and the folds-forming animation (a fresh solve + grid per frame, frames in parallel over
// TBB, then relaxed in order with warm starts).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "foldcast/drape/drape.hpp"
#include "foldcast/drape/relax.hpp"

namespace {
using namespace foldcast::drape;

ClothParams cotton() {
    return cloth_from_look(foldcast::looks::Mechanics{}, 0.5, 0.7, 0.1);  // 4 folds
}

void BM_SolveFolds(benchmark::State& state) {
    ClothParams p = cotton();
    p.thickness_m = state.range(0) * 1e-6;  // thinner cloth: more fold counts to try
    int folds = 0;
    for (auto _ : state) {
        const FoldSolution s = solve_folds(p);
        folds = s.folds;
        benchmark::DoNotOptimize(s.zmax_m);
    }
    state.counters["folds"] = folds;
}
BENCHMARK(BM_SolveFolds)->Arg(300)->Arg(100)->Unit(benchmark::kMicrosecond);

// The model's grid alone (relax = false): the baseline the relaxation is measured against.
void BM_BuildGarment(benchmark::State& state) {
    const ClothParams p = cotton();
    const FoldSolution s = solve_folds(p);
    const GridSize grid{int(state.range(0)), int(state.range(0))};
    for (auto _ : state) {
        const Garment g = build_garment(p, s, grid, false);
        benchmark::DoNotOptimize(g.mesh.positions.data());
    }
    state.counters["vertices"] = double(grid.nu) * grid.nv;
}
BENCHMARK(BM_BuildGarment)->Arg(64)->Arg(256)->Unit(benchmark::kMillisecond);

// What `foldcast drape` does for a still: one solve, the grid, its relaxation (budget:
// 20 ms at 64x64).  Iterations and stretch after are reported beside the time.
void BM_SolveGridRelax(benchmark::State& state) {
    const ClothParams p = cotton();
    const GridSize grid{int(state.range(0)), int(state.range(0))};
    Garment g;
    for (auto _ : state) {
        g = build_garment(p, solve_folds(p), grid);
        benchmark::DoNotOptimize(g.mesh.positions.data());
    }
    state.counters["iterations"] = g.relax_iterations;
    state.counters["stretch_max"] = g.stretch.max;
}
BENCHMARK(BM_SolveGridRelax)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);

// What the relaxed frames look like beside the model's own (after the timed runs): the worst
// frame's stretch, the crests on the centre fibre (on frames with the model's fold count:
// the median and the largest distance of a crest from the model's, and the last frame's), and
// the last frame's 90th-percentile turn between quads (crumpling).
void report_animation_quality(const ClothParams& p, GridSize grid, AnimationOptions options, benchmark::State& state) {
    const foldcast::Animation relaxed = animate(p, grid, options);
    options.relax = false;
    const foldcast::Animation model = animate(p, grid, options);
    double worst_mean = 0.0, worst_max = 0.0, last_crest = 0.0;
    std::vector<double> crest;  // per frame with the model's fold count: its farthest crest
    for (std::size_t f = 0; f < relaxed.frames.size(); ++f) {
        const Stretch s = measure_stretch(relaxed.frames[f], p, grid);
        worst_mean = std::max(worst_mean, s.mean), worst_max = std::max(worst_max, s.max);
        const CentreFibreFolds a = centre_fibre_folds(relaxed.frames[f], grid);
        const CentreFibreFolds b = centre_fibre_folds(model.frames[f], grid);
        if (a.crest_heights_m.size() != b.crest_heights_m.size()) continue;
        double farthest = 0.0;
        for (std::size_t c = 0; c < a.crest_heights_m.size(); ++c)
            farthest = std::max(farthest, std::abs(a.crest_heights_m[c] - b.crest_heights_m[c]));
        crest.push_back(farthest);
        if (f + 1 == relaxed.frames.size()) last_crest = farthest;
    }
    std::sort(crest.begin(), crest.end());
    state.counters["stretch_mean_worst"] = worst_mean;
    state.counters["stretch_max_worst"] = worst_max;
    state.counters["crest_mm_median"] = crest.empty() ? 0.0 : 1e3 * crest[crest.size() / 2];
    state.counters["crest_mm_max"] = crest.empty() ? 0.0 : 1e3 * crest.back();
    state.counters["crest_mm_last"] = 1e3 * last_crest;
    state.counters["turn_last_rad"] = turn_p90(relaxed.frames.back(), grid);
}

// Args: grid side, frames, relax (0/1).  Budget with relaxation: 256x256 x 120 frames < 2 s
// on 2 cores.
void BM_Animate(benchmark::State& state) {
    const ClothParams p = cotton();
    const GridSize grid{int(state.range(0)), int(state.range(0))};
    AnimationOptions options;
    options.frames = int(state.range(1));
    options.relax = state.range(2) != 0;
    options.sway_amplitude_m = 0.02;
    for (auto _ : state) {
        const foldcast::Animation anim = animate(p, grid, options);
        benchmark::DoNotOptimize(anim.frames.back().data());
    }
    state.counters["vertex_frames/s"] =
        benchmark::Counter(double(grid.nu) * grid.nv * options.frames, benchmark::Counter::kIsIterationInvariantRate);
    if (options.relax) report_animation_quality(p, grid, options, state);
}
BENCHMARK(BM_Animate)
    ->Args({256, 120, 0})
    ->Args({256, 120, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
