// drape throughput: one fold solve, one garment grid (with and without its relaxation),
// and the folds-forming animation (a fresh solve + grid per frame, frames in parallel over
// TBB, then relaxed in order with warm starts).
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
}
BENCHMARK(BM_Animate)
    ->Args({256, 120, 0})
    ->Args({256, 120, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
