// bench_vessel: the whole HCLM -> surface pipeline (parse + smooth + control mesh + level-2
// Catmull-Clark limit surface) for the largest bundled case (cases/neuro.hclm) and a random
// 100-segment tree, with the stages timed separately. Mesh sizes are printed as counters.
// Target (issue 3): <= 20 ms on one core for the 100-segment tree at M = 8, L = 2.
// Peers in the same run: the pipeline with OpenSubdiv's PrimvarRefiner::Limit instead of the
// limit masks (BM_Tree100PipelineOsdLimit), and with OpenSubdiv refining level 2 itself before the
// same masks instead of the last step done by hand (BM_Tree100PipelineOsdLevel2; same mesh).
#include <fstream>
#include <sstream>
#include <string>

#include <benchmark/benchmark.h>

#include "vessel/case_generator.hpp"
#include "vessel/centerline_smoother.hpp"
#include "vessel/control_mesh_builder.hpp"
#include "vessel/hclm.hpp"
#include "vessel/subdivision.hpp"
#include "vessel/vessel_graph.hpp"

namespace {

using namespace cathbox::vessel;

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

const std::string& neuro_text() {
  static const std::string text = read_file(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro.hclm");
  return text;
}

// The random 100-segment tree at the generator's default density (a point every 1.2 radii,
// ~10 points per segment) and a sparser one (a point every 2.5 radii, ~5 per segment).
const std::string& tree_text() {
  static const std::string text = write_hclm(CaseGenerator::random_tree(2026, RandomTreeOptions{}));
  return text;
}
const std::string& sparse_tree_text() {
  static const std::string text = [] {
    RandomTreeOptions options;
    options.spacing_radii = 2.5;
    return write_hclm(CaseGenerator::random_tree(2026, options));
  }();
  return text;
}

// Parse + smooth + control mesh + subdivision, timed as one.
void pipeline(benchmark::State& state, const std::string& text, int ring_points,
              LimitMethod method = LimitMethod::kMasks) {
  MeshOptions options;
  options.ring_points = ring_points;
  std::size_t triangles = 0, vertices = 0, control_faces = 0, segments = 0, points = 0;
  for (auto _ : state) {
    const HclmReadResult read = read_hclm(text);
    const VesselGraph graph(read.model);
    const VesselModel smoothed = smooth_centerlines(read.model, graph, options.smoothing_passes);
    const ControlMeshResult control = build_control_mesh(smoothed, graph, options);
    const SurfaceMeshResult surface = subdivide(control.mesh, options.subdivision_level, method);
    if (!read.ok() || !control.ok() || !surface.ok()) state.SkipWithError("pipeline failed");
    triangles = surface.mesh.triangle_count();
    vertices = surface.mesh.vertex_count();
    control_faces = control.mesh.face_count();
    segments = read.model.segments.size();
    points = read.model.point_count();
    benchmark::DoNotOptimize(surface.mesh.positions_mm.data());
  }
  state.counters["segments"] = static_cast<double>(segments);
  state.counters["points"] = static_cast<double>(points);
  state.counters["control_faces"] = static_cast<double>(control_faces);
  state.counters["vertices"] = static_cast<double>(vertices);
  state.counters["triangles"] = static_cast<double>(triangles);
}

// The stages separately (state.range(0): 0 parse, 1 smooth, 2 control mesh, 3 subdivision).
void stage(benchmark::State& state, const std::string& text) {
  const MeshOptions options;
  const HclmReadResult read = read_hclm(text);
  const VesselGraph graph(read.model);
  const VesselModel smoothed = smooth_centerlines(read.model, graph, options.smoothing_passes);
  const ControlMeshResult control = build_control_mesh(smoothed, graph, options);
  for (auto _ : state) {
    switch (state.range(0)) {
      case 0: benchmark::DoNotOptimize(read_hclm(text).model.segments.data()); break;
      case 1: benchmark::DoNotOptimize(smooth_centerlines(read.model, graph, options.smoothing_passes).segments.data()); break;
      case 2: benchmark::DoNotOptimize(build_control_mesh(smoothed, graph, options).mesh.positions_mm.data()); break;
      default: benchmark::DoNotOptimize(subdivide(control.mesh, options.subdivision_level).mesh.positions_mm.data()); break;
    }
  }
}

void BM_NeuroPipeline(benchmark::State& state) { pipeline(state, neuro_text(), static_cast<int>(state.range(0))); }
void BM_Tree100Pipeline(benchmark::State& state) { pipeline(state, tree_text(), static_cast<int>(state.range(0))); }
// Peer: the same pipeline with OpenSubdiv's own PrimvarRefiner::Limit (full last-level topology).
void BM_Tree100PipelineOsdLimit(benchmark::State& state) {
  pipeline(state, tree_text(), static_cast<int>(state.range(0)), LimitMethod::kOpenSubdiv);
}
// Peer: OpenSubdiv refines level L (faces only) and PrimvarRefiner interpolates it, then the masks.
void BM_Tree100PipelineOsdLevel2(benchmark::State& state) {
  pipeline(state, tree_text(), static_cast<int>(state.range(0)), LimitMethod::kMasksOnRefinedLevel);
}
void BM_SparseTree100Pipeline(benchmark::State& state) {
  pipeline(state, sparse_tree_text(), static_cast<int>(state.range(0)));
}
void BM_Tree100Stage(benchmark::State& state) { stage(state, tree_text()); }
void BM_NeuroStage(benchmark::State& state) { stage(state, neuro_text()); }

BENCHMARK(BM_Tree100Pipeline)->Arg(8)->Arg(4)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Tree100PipelineOsdLimit)->Arg(8)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Tree100PipelineOsdLevel2)->Arg(8)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SparseTree100Pipeline)->Arg(8)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NeuroPipeline)->Arg(8)->Arg(4)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Tree100Stage)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NeuroStage)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
