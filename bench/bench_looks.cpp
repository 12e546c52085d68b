// looks: cost of the procedural weave hook per shading point (render calls it once per
// camera-ray hit on the garment) and of loading the look library.
#include <benchmark/benchmark.h>

#include <cmath>

#include "foldcast/looks/looks.hpp"
#include "foldcast/looks/weave.hpp"

using namespace foldcast::looks;

namespace {
// Footprint in yarn pitches: 0 = unfiltered, 0.2 = 4-tap box, 0.5 = 4-tap + fade, 2 = mean.
void BM_SampleWeave(benchmark::State& state) {
    Appearance a;
    a.weave = static_cast<Weave>(state.range(0));
    a.twill_float = 3;
    a.repeat_mm = 0.45;
    const double pitch = a.repeat_mm * 1e-3;
    const double footprint = static_cast<double>(state.range(1)) / 10.0 * pitch;
    double u = 0.0, v = 0.0;
    for (auto _ : state) {
        u += 0.61803 * pitch;
        v += 0.41421 * pitch;
        benchmark::DoNotOptimize(sample_weave(a, {u, v}, footprint));
    }
    state.SetItemsProcessed(state.iterations());
    state.SetLabel(std::string(weave_name(a.weave)) + " footprint " + std::to_string(state.range(1) / 10.0) + " yarns");
}
BENCHMARK(BM_SampleWeave)
    ->ArgsProduct({{static_cast<int>(Weave::plain), static_cast<int>(Weave::twill), static_cast<int>(Weave::satin),
                    static_cast<int>(Weave::knit)},
                   {0, 2, 5, 20}});

void BM_LoadDefaultLibrary(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(Library::load_default());
}
BENCHMARK(BM_LoadDefaultLibrary)->Unit(benchmark::kMillisecond);
}  // namespace

BENCHMARK_MAIN();
