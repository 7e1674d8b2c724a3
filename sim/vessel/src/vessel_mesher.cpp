#include "vessel/vessel_mesher.hpp"

#include <optional>

#include "junction_fit.hpp"
#include "vessel/centerline_smoother.hpp"
#include "vessel/control_mesh_builder.hpp"
#include "vessel/hclm.hpp"
#include "vessel/subdivision.hpp"
#include "vessel/vessel_graph.hpp"

namespace cathbox::vessel {

namespace {

// Validation and the smoothed centreline, which every surface starts from. Null with out.error
// set when the model is refused.
std::optional<VesselGraph> smooth_into(VesselSurface& out, const VesselModel& model, const MeshOptions& options) {
  if (const std::vector<Diagnostic> problems = validate_model(model); !problems.empty()) {
    out.error = problems.front().to_string();
    return std::nullopt;
  }
  if (model.segments.empty()) {
    out.error = "the model has no segments";
    return std::nullopt;
  }
  std::optional<VesselGraph> graph(std::in_place, model);
  out.euler_characteristic = graph->surface_euler_characteristic();
  out.smoothed = smooth_centerlines(model, *graph, options.smoothing_passes, options.trim_at_junctions, options.smoothing);
  if (!options.caps) out.euler_characteristic -= static_cast<int>(graph->free_ends().size());
  return graph;
}

}  // namespace

VesselSurface build_vessel_surface(const VesselModel& model, SurfaceMesh made, const MeshOptions& options) {
  VesselSurface out;
  if (!smooth_into(out, model, options)) return out;
  if (made.triangle_count() == 0) {
    out.error = "the given vessel surface has no triangles";
    return out;
  }
  out.mesh = std::move(made);
  return out;
}

VesselSurface build_vessel_surface(const VesselModel& model, const MeshOptions& options) {
  VesselSurface out;
  const std::optional<VesselGraph> smoothed_graph = smooth_into(out, model, options);
  if (!smoothed_graph) return out;
  const VesselGraph& graph = *smoothed_graph;
  ControlMeshResult control = build_control_mesh(out.smoothed, graph, options);
  if (!control.ok()) {
    out.error = control.error().message;
    return out;
  }
  out.control = std::move(*control);
  std::optional<detail::JunctionFit> fit;
  LevelAdjuster adjust;
  if (options.fit_junctions && options.subdivision_level > 0) {
    fit.emplace(out.smoothed, graph, out.control);
    if (!fit->empty()) adjust = [&fit](RefinedLevel& level) { fit->apply(level); };
  }
  SurfaceMeshResult surface = subdivide(out.control, options.subdivision_level, options.limit_method, adjust);
  if (!surface.ok()) {
    out.error = surface.error().message;
    return out;
  }
  out.mesh = std::move(*surface);
  return out;
}

VesselSurface load_vessel_surface(const std::string& hclm_path, const MeshOptions& options) {
  HclmReadResult read = load_hclm(hclm_path);
  if (!read.ok()) {
    VesselSurface out;
    out.error = read.errors.front().to_string();
    return out;
  }
  VesselSurface out = build_vessel_surface(read.model, options);
  if (!out.ok()) out.error = hclm_path + ": " + out.error;
  return out;
}

SurfaceMeshLoad load_surface_mesh(const std::string& hclm_path, const MeshOptions& options) {
  VesselSurface surface = load_vessel_surface(hclm_path, options);
  if (!surface.ok()) return base::Error{std::move(surface.error)};
  return SurfaceMeshLoad(std::move(surface.mesh));
}

}  // namespace cathbox::vessel
