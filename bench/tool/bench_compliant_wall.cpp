// bench_compliant_wall: what moving the compliant wall with the pulse costs per 1 ms tick (issue
// 29: "the tree is refit, or the displacement lives in a field the queries read"), on the bundled
// neuro case's meshed wall and the SOFA surface case (cases/sofa_aneurysm):
//   BM_PulseField       the field: every segment's Laplace displacement set (CaseWallField)
//   BM_MoveVertices     the least a refit must do: every vertex moved along its normal
//   BM_TreeRebuild      the collision tree built again on the moved mesh (no refit exists;
//                       a refit still visits every node and triangle)
//   BM_Probe / BM_ProbeDisplaced   one wall query near the wall, bare and through the field
#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <vector>

#include "collision/obb_tree.hpp"
#include "scenario/case_file.hpp"
#include "scenario/case_wall.hpp"
#include "scenario/case_world.hpp"

namespace {

using namespace cathbox;

struct Loaded {
  std::unique_ptr<tool::CaseWorld> world;
  std::unique_ptr<tool::CaseWallField> field;
};

const Loaded& loaded(int which) {
  static Loaded cases[2];
  Loaded& l = cases[which];
  if (!l.world) {
    const std::string path = std::string(CATHBOX_SOURCE_DIR) + (which == 0 ? "/cases/neuro.case" : "/cases/sofa_aneurysm/sofa_aneurysm.case");
    tool::CaseParse c = tool::load_case(path);
    if (!c) std::abort();
    tool::WorldBuild w = tool::build_world(*c);
    if (!w) std::abort();
    l.world = std::move(*w);
    const tool::CaseWall wall{tool::Territory::kIntracranial, 0.0};
    l.field = tool::make_case_wall_field(&wall, l.world->wall(), l.world->source_model());
  }
  return l;
}

const char* name(int which) { return which == 0 ? "neuro" : "sofa_surface"; }

void BM_PulseField(benchmark::State& state) {
  const Loaded& l = loaded(static_cast<int>(state.range(0)));
  double p = 0.0;
  for (auto _ : state) {
    p = p > 5.0 ? -5.0 : p + 0.01;
    l.field->set_pressure_kPa(p);
    benchmark::ClobberMemory();
  }
  state.SetLabel(std::string(name(static_cast<int>(state.range(0)))) + ", " +
                 std::to_string(l.field->distension().segment_count()) + " segments");
}

void BM_MoveVertices(benchmark::State& state) {
  const Loaded& l = loaded(static_cast<int>(state.range(0)));
  vessel::SurfaceMesh mesh = *l.world->mesh();
  for (auto _ : state) {
    for (std::size_t v = 0; v < mesh.positions_mm.size(); ++v) mesh.positions_mm[v] += mesh.normals[v] * 1e-4F;
    benchmark::DoNotOptimize(mesh.positions_mm.data());
  }
  state.SetLabel(std::string(name(static_cast<int>(state.range(0)))) + ", " + std::to_string(mesh.positions_mm.size()) + " vertices");
}

void BM_TreeRebuild(benchmark::State& state) {
  const Loaded& l = loaded(static_cast<int>(state.range(0)));
  const vessel::SurfaceMesh& mesh = *l.world->mesh();
  for (auto _ : state) {
    collision::TreeBuild tree = collision::ObbTree::build(mesh);
    benchmark::DoNotOptimize(tree);
  }
  state.SetLabel(std::string(name(static_cast<int>(state.range(0)))) + ", " + std::to_string(mesh.triangle_count()) + " triangles");
}

// Probes at the case's entry, 0.2 mm nodes, as a tool node near the wall.
void probe_loop(benchmark::State& state, const tool::WallModel& wall, const tool::Entry& entry) {
  tool::WallProbe probe;
  probe.radius_mm = 0.2;
  tool::WallHint hint;
  tool::WallContact out;
  int k = 0;
  for (auto _ : state) {
    probe.center_mm = entry.point_mm + entry.direction * (0.01 * (k++ % 100));
    benchmark::DoNotOptimize(wall.probe(probe, hint, out));
  }
}

void BM_Probe(benchmark::State& state) {
  const Loaded& l = loaded(static_cast<int>(state.range(0)));
  probe_loop(state, l.world->wall(), l.world->entry());
  state.SetLabel(name(static_cast<int>(state.range(0))));
}

void BM_ProbeDisplaced(benchmark::State& state) {
  const Loaded& l = loaded(static_cast<int>(state.range(0)));
  l.field->set_pressure_kPa(3.0);
  probe_loop(state, l.field->wall(), l.world->entry());
  state.SetLabel(name(static_cast<int>(state.range(0))));
}

}  // namespace

BENCHMARK(BM_PulseField)->Arg(0)->Arg(1);
BENCHMARK(BM_MoveVertices)->Arg(0)->Arg(1);
BENCHMARK(BM_TreeRebuild)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Probe)->Arg(0)->Arg(1);
BENCHMARK(BM_ProbeDisplaced)->Arg(0)->Arg(1);
BENCHMARK_MAIN();
