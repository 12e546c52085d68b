// drape throughput: one fold solve, one garment grid, and the folds-forming animation
// (a fresh solve + grid per frame, frames in parallel over TBB).
#include <benchmark/benchmark.h>

#include "foldcast/drape.hpp"

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

void BM_BuildGarment(benchmark::State& state) {
    const ClothParams p = cotton();
    const FoldSolution s = solve_folds(p);
    const GridSize grid{int(state.range(0)), int(state.range(0))};
    for (auto _ : state) {
        const Garment g = build_garment(p, s, grid);
        benchmark::DoNotOptimize(g.mesh.positions.data());
    }
    state.counters["vertices"] = double(grid.nu) * grid.nv;
}
BENCHMARK(BM_BuildGarment)->Arg(64)->Arg(256)->Unit(benchmark::kMillisecond);

void BM_Animate(benchmark::State& state) {
    const ClothParams p = cotton();
    const GridSize grid{int(state.range(0)), int(state.range(0))};
    AnimationOptions options;
    options.frames = int(state.range(1));
    options.sway_amplitude_m = 0.02;
    for (auto _ : state) {
        const foldcast::Animation anim = animate(p, grid, options);
        benchmark::DoNotOptimize(anim.frames.back().data());
    }
    state.counters["vertex_frames/s"] = benchmark::Counter(
        double(grid.nu) * grid.nv * options.frames, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Animate)->Args({256, 120})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
