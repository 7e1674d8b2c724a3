#pragma once
// bench_tool's benchmarks, registered in bench_tool.cpp in the order they run (its header says
// what each times), defined one concept per file.
#include <benchmark/benchmark.h>

namespace cathbox::bench {

// navigation_steps.cpp
void BM_StepCoaxial(benchmark::State& state);
void BM_StepSeparate(benchmark::State& state);
void BM_DualDeviceRandom6ms(benchmark::State& state);
// triaxial_steps.cpp
void BM_StepTriaxial(benchmark::State& state);
void BM_WallReprobe(benchmark::State& state);
// coil_steps.cpp
void BM_StepCoilDeploy(benchmark::State& state);
void BM_StepCoilPacking(benchmark::State& state);
void BM_StepCoilPackingPaced(benchmark::State& state);
// stent_retriever_steps.cpp
void BM_StepStentRetriever(benchmark::State& state);
void BM_StepStentRetrieverCase(benchmark::State& state);

}  // namespace cathbox::bench
