// Time per 1 ms simulated step: a guidewire of 200 inserted nodes and a catheter of 150, in
// the neuro case (or, without the vessel module, a meshed tube of neuro-like size and
// tortuosity), in contact with the wall, driven by small push-pull and twist inputs.
// Target: <= 250 us per step on one core. Published simulators on SOFA's BeamAdapter run at
// about 20-150 Hz (7-50 ms per step); the figures here are printed beside that.
//
//   coaxial: the wire runs inside the catheter (composite model: only the wire beyond the
//            catheter tip is solved separately);
//   separate: the same two tools solved as two independent rods (350 solved nodes).
//   triaxial: guide catheter (150 inserted nodes) > microcatheter (200) > microwire (200), the
//            same neuro path and hand input (issue 16: median <= 300 us, p99 <= 600 us);
//   dual device random 6 ms: host/python's DualDevice-v0 under random actions at a 6 ms tick,
//            the simulator alone (per env step of 22 ticks; see BM_DualDeviceRandom6ms);
//   coil deploy: a 150 mm coil (0.5 mm spacing, helical rest shape, 5 mm loops) pushed at 20
//            mm/s out of a microcatheter into a 6.4 mm sphere on a 2 mm artery, touching its
//            own loops and the catheter's tip (issue 16: median <= 400 us);
//   coil packing: the same sphere already holding 300 mm of coil (a 150 mm, 5 mm framing coil
//            and a 150 mm, 4 mm filling coil, each pushed at 20 mm/s and detached, 10.8 % of the
//            sphere cap), a 100 mm, 3 mm finishing coil pushed in at 20 mm/s (issue 29: its
//            median and p99 beside the coil deploy's; the tick's budget is 1,000 us).
//   coil packing paced: the same push stepped every 1 ms of the steady clock as the haptic loop
//            steps it, the released coils' job left running into the wait for the next tick
//            (Simulator::set_released_overlap, as the session runs it): each tick's latency
//            from its start to the step's return, and the ticks late.
//   stent retriever across a clot: a 4 x 20 mm stent retriever in a 2.8 mm artery (the M1
//            clot's size) past a 90 degree bend, unsheathed by pulling its microcatheter back
//            25 mm at 5 mm/s (5000 steps), then pulled back 40 mm at 10 mm/s dragging an
//            integrated clot (its 78 mN of wall friction and head, the bundled M1 clot's) (4000
//            steps): median and p99 of both phases (issue 30: p99 <= 500 us).
//   stent retriever, bundled case: cases/neuro_thrombectomy_m1_stentretriever on its mesh,
//            driven by its own script: 2 s of the dwell, then the retrieval (dwell_, retrieval_
//            and overall median and p99; the same target).
//
// Files: navigation_steps.cpp (coaxial, separate, dual device), triaxial_steps.cpp (triaxial,
// wall reprobe), coil_steps.cpp, stent_retriever_steps.cpp; their shared parts bench_world
// (the wall), step_times.hpp (per-step timing), counting_wall.hpp (wall probes).
#include <cstdio>

#include <benchmark/benchmark.h>

#include "tool_benchmarks.hpp"

namespace {

using namespace cathbox::bench;

BENCHMARK(BM_StepCoaxial)->Unit(benchmark::kMicrosecond)->Iterations(5000);
BENCHMARK(BM_DualDeviceRandom6ms)->Unit(benchmark::kMicrosecond)->Iterations(750);  // 10 episodes of 75 steps
BENCHMARK(BM_StepSeparate)->Unit(benchmark::kMicrosecond)->Iterations(5000);
BENCHMARK(BM_StepTriaxial)->Unit(benchmark::kMicrosecond)->Iterations(5000);
BENCHMARK(BM_WallReprobe)->ArgName("fused")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3)->Repetitions(5);
BENCHMARK(BM_StepCoilDeploy)->Unit(benchmark::kMicrosecond)->Iterations(7400);  // 148 mm of coil
BENCHMARK(BM_StepCoilPacking)->Unit(benchmark::kMicrosecond)->Iterations(4000);  // 80 mm of the third coil
BENCHMARK(BM_StepCoilPackingPaced)->ArgName("overlap")->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond)->Iterations(4000);  // as the haptic loop runs it
BENCHMARK(BM_StepStentRetriever)->Unit(benchmark::kMicrosecond)->Iterations(9000);  // unsheathing, then retrieval
BENCHMARK(BM_StepStentRetrieverCase)->Unit(benchmark::kMicrosecond)->Iterations(14000);  // dwell 2 s, retrieval 12 s

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  std::printf("Peers: SOFA BeamAdapter catheter/guidewire simulators, about 20-150 Hz = 6700-50000 us per step "
              "(published); target here <= 250 us per 1 ms step on one core.\n");
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
