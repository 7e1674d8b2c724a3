#include "vessel/vessel_mesher.hpp"

#include <optional>

#include "junction_fit.hpp"
#include "vessel/centerline_smoother.hpp"
#include "vessel/control_mesh_builder.hpp"
#include "vessel/hclm.hpp"
#include "vessel/subdivision.hpp"
#include "vessel/vessel_graph.hpp"

namespace cathbox::vessel {

VesselSurface build_vessel_surface(const VesselModel& model, const MeshOptions& options) {
  VesselSurface out;
  if (const std::vector<Diagnostic> problems = validate_model(model); !problems.empty()) {
    out.error = problems.front().to_string();
    return out;
  }
  if (model.segments.empty()) {
    out.error = "the model has no segments";
    return out;
  }
  const VesselGraph graph(model);
  out.euler_characteristic = graph.surface_euler_characteristic();
  out.smoothed = smooth_centerlines(model, graph, options.smoothing_passes, options.trim_at_junctions, options.smoothing);
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
  if (!options.caps) out.euler_characteristic -= static_cast<int>(graph.free_ends().size());
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
