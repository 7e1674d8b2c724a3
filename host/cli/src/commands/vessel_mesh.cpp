// `cathbox vessel mesh`: the vessel surface to a mesh file (vessel.cpp has the group).
#include <cstdio>
#include <string>
#include <thread>

#include <malloc.h>

#include "cli/args.hpp"
#include "cli/exit_codes.hpp"
#include "cli/usage.hpp"
#include "session/haptic_memory.hpp"
#include "vessel/control_mesh_builder.hpp"
#include "vessel/mesh_analysis.hpp"
#include "vessel/mesh_export.hpp"
#include "vessel/vessel_mesher.hpp"
#include "vessel_commands.hpp"

namespace cathbox::cli {
namespace {

// Meshing allocates and frees a few hundred bytes per output triangle in large blocks (the
// subdivision levels, then the mesh check's edge lists): kept in the heap
// (session::keep_freed_memory says why), each page is faulted in once, not once per block (~1 us
// a page on a virtual machine, a quarter of the command's time at 7M triangles). One arena for
// every thread, so that the check running beside the writer (run_mesh) reuses the subdivision's
// freed memory too instead of faulting in an arena of its own.
void keep_freed_memory_in_one_arena() {
  session::keep_freed_memory();
  mallopt(M_ARENA_MAX, 1);
}

}  // namespace

int run_mesh(cli::Args& args, const cli::GroupSpec& group) {
  const auto usage_error = [&](const std::string& what) { return cli::usage_error(group, what); };
  if (args.positionals().size() != 1) return usage_error("mesh takes one FILE");
  const auto output = args.value("output");
  if (!output) return usage_error("mesh needs -o OUT.obj|.ply|.stl|.cbxmesh");
  vessel::MeshOptions options;
  if (const auto m = args.integer("ring")) options.ring_points = static_cast<int>(*m);
  if (const auto l = args.integer("level")) options.subdivision_level = static_cast<int>(*l);
  if (const auto s = args.integer("smooth")) options.smoothing_passes = static_cast<int>(*s);
  if (!args.ok()) return usage_error(args.error());
  if (options.ring_points < 3 || options.ring_points > 64) return usage_error("--ring must be 3..64");
  if (options.subdivision_level < 0 || options.subdivision_level > 5) return usage_error("--level must be 0..5");
  if (options.smoothing_passes < 0 || options.smoothing_passes > 100) return usage_error("--smooth must be 0..100");
  if (const auto method = args.value("smoothing")) {
    if (*method == "taubin") options.smoothing = vessel::SmoothingMethod::kTaubin;
    else if (*method == "moving-average") options.smoothing = vessel::SmoothingMethod::kMovingAverage;
    else return usage_error("--smoothing must be taubin or moving-average");
  }
  if (const auto rings = args.value("rings")) {
    if (*rings == "adaptive") options.ring_placement = vessel::RingPlacement::kAdaptive;
    else if (*rings == "per-point") options.ring_placement = vessel::RingPlacement::kPerPoint;
    else return usage_error("--rings must be adaptive or per-point");
  }
  options.caps = !args.flag("no-caps");
  options.trim_at_junctions = !args.flag("no-trim");
  options.fit_junctions = !args.flag("no-junction-fit");
  options.junction_fallback = !args.flag("no-junction-fallback");
  if (args.flag("control-mesh")) options.subdivision_level = 0;
  const std::string& path = args.positionals()[0];
  const auto model = read_model(path);
  if (!model) return cli::kExitBadInput;
  keep_freed_memory_in_one_arena();
  const vessel::VesselSurface surface = vessel::build_vessel_surface(*model, options);
  if (!surface.ok()) {
    std::fprintf(stderr, "%s: %s\n", path.c_str(), surface.error.c_str());
    return cli::kExitBadInput;
  }
  // The check (about a sixth of the command's CPU) runs on a second thread while this one writes
  // the file (its copy into the page cache is most of the writing): both only read the mesh.
  vessel::MeshAnalysis a;
  std::thread check([&a, &surface] { a = vessel::analyze_mesh(surface.mesh); });
  const std::string error = vessel::write_mesh(surface.mesh, *output);
  check.join();
  if (!error.empty()) {
    std::fprintf(stderr, "cathbox vessel mesh: %s\n", error.c_str());
    return error.rfind("unknown mesh format", 0) == 0 ? cli::kExitBadInput : cli::kExitFailure;
  }
  std::printf("%s: control mesh %zu vertices %zu faces; surface %zu vertices %zu triangles; euler %d; %s, %s; "
              "volume %.1f mm3\n",
              output->c_str(), surface.control.vertex_count(), surface.control.face_count(), a.vertices, a.triangles,
              a.euler_characteristic, a.closed() ? "closed" : "open", a.manifold() ? "manifold" : "NOT manifold",
              a.signed_volume_mm3);
  if (const std::string fallback = vessel::fallback_summary(surface.control); !fallback.empty()) {
    std::printf("%s: %s\n", output->c_str(), fallback.c_str());
  }
  return cli::kExitOk;
}

}  // namespace cathbox::cli
