// The rod step as the WebAssembly session runs it, built twice from this one file: natively
// (bench_wasm) and by emscripten (bench_wasm.js, run by node), so the two medians come from the
// same code on the same machine (scripts/bench-wasm prints them side by side and their ratio;
// issue 36's goal: wasm <= 2x native).
//   Workload: bench_tool's "separate" step (bench/rod_navigation.hpp): a catheter (150 inserted
//   nodes) and a guidewire (200) solved as two rods in the neuro case's vessel, a hand pushing
//   and pulling 1 mm and twisting a little. The vessel surface is the CBXMESH2 file given by --mesh=FILE
//   (`cathbox vessel mesh cases/neuro.hclm -o neuro.cbxmesh`), for both builds: wasm cannot mesh.
//   Counters: median_us and p99_us of the step's wall time (steady clock), and the wire's tip
//   depth and hand force after the run, which must agree between the two builds (same answer).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>

#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"
#include "tool/simulator.hpp"
#include "vessel/mesh_wire.hpp"
#include "../rod_navigation.hpp"

namespace {

using namespace cathbox::tool;

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// --mesh=FILE (node does not pass the environment into the wasm program).
std::string g_mesh_path;

// The neuro case's world on the given surface; null with the reason printed.
std::unique_ptr<CaseWorld> neuro_world() {
  if (g_mesh_path.empty()) {
    std::fprintf(stderr, "bench_wasm: give --mesh=FILE, the neuro case's .cbxmesh\n");
    return nullptr;
  }
  const char* mesh_path = g_mesh_path.c_str();
  const std::string wire = read_all(mesh_path);
  const auto mesh = cathbox::vessel::decode_mesh_wire(
      std::span(reinterpret_cast<const std::uint8_t*>(wire.data()), wire.size()));
  if (!mesh) {
    std::fprintf(stderr, "bench_wasm: %s: %s\n", mesh_path, mesh.error().message.c_str());
    return nullptr;
  }
  const std::string case_path = std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro.case";
  const CaseParse c = load_case(case_path);
  if (!c) {
    std::fprintf(stderr, "bench_wasm: %s\n", c.error().message.c_str());
    return nullptr;
  }
  WorldBuild built = build_world(*c, read_all(c->vessel_path), &mesh.value());
  if (!built) {
    std::fprintf(stderr, "bench_wasm: %s\n", built.error().message.c_str());
    return nullptr;
  }
  return std::move(*built);
}

double pick(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

void BM_RodStepSeparate(benchmark::State& state) {
  static const std::unique_ptr<CaseWorld> world = neuro_world();
  if (!world) {
    state.SkipWithError("no neuro world (--mesh=FILE)");
    return;
  }
  cathbox::bench::RodNavigation nav(false);
  Simulator sim(world->wall(), nav.tools, world->entry());
  nav.navigate_in(sim);
  std::vector<double> wall_us;
  wall_us.reserve(1 << 14);
  std::uint64_t i = 0;
  for (auto _ : state) {
    nav.hold(sim, i++);
    const auto t0 = std::chrono::steady_clock::now();
    sim.step();
    wall_us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
  }
  state.counters["median_us"] = pick(wall_us, 0.5);
  state.counters["p99_us"] = pick(wall_us, 0.99);
  state.counters["wire_tip_depth_mm"] = glm::dot(sim.tip(1).position_mm - world->entry().point_mm, world->entry().direction);
  state.counters["wire_force_mN"] = sim.hand_force_mN(1);
  state.SetLabel("neuro case, catheter 150 + wire 200 nodes");
}

}  // namespace

BENCHMARK(BM_RodStepSeparate)->Unit(benchmark::kMicrosecond)->Iterations(3000);

int main(int argc, char** argv) {
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.starts_with("--mesh=")) {
      g_mesh_path = arg.substr(7);
    } else {
      rest.push_back(argv[i]);
    }
  }
  int n = static_cast<int>(rest.size());
  benchmark::Initialize(&n, rest.data());
  if (benchmark::ReportUnrecognizedArguments(n, rest.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
