#include <ctime>

#include "server/upload_limits.hpp"
#include "vessel/centerline_smoother.hpp"
#include "vessel/control_mesh_builder.hpp"
#include "vessel/hclm.hpp"
#include "vessel/mesh_options.hpp"
#include "vessel/vessel_graph.hpp"

namespace cathbox::server {

double thread_cpu_seconds() {
  timespec t{};
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t) != 0) return 0.0;
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

Status check_vessel_bounds(std::string_view hclm_text, const std::string& file, const UploadLimits& limits, int subdivision_level,
                           int ring_points) {
  if (hclm_text.empty()) return Ok{};
  const vessel::HclmReadResult read = vessel::read_hclm(hclm_text, file);
  if (!read.ok()) return Ok{};
  std::int64_t points = 0;
  for (const vessel::Segment& s : read.model.segments) points += static_cast<std::int64_t>(s.points.size());
  if (points > limits.max_vessel_points) {
    return make_error(413, file + ": " + std::to_string(points) + " centreline points; the limit is " +
                               std::to_string(limits.max_vessel_points));
  }
  // The control mesh is a ring of M points every few millimetres: cheap next to its subdivision.
  // Catmull-Clark makes an n-sided face n quads, then every quad four at each further level; a
  // quad is two triangles.
  vessel::MeshOptions options;
  options.subdivision_level = subdivision_level;
  options.ring_points = ring_points;
  if (read.model.segments.empty() || !vessel::validate_model(read.model).empty()) return Ok{};
  const vessel::VesselGraph graph(read.model);
  const vessel::VesselModel smoothed =
      vessel::smooth_centerlines(read.model, graph, options.smoothing_passes, options.trim_at_junctions, options.smoothing);
  const vessel::ControlMeshResult control = vessel::build_control_mesh(smoothed, graph, options);
  if (!control.ok()) return Ok{};
  std::int64_t corners = 0;
  for (const int n : control->face_sizes) corners += n;
  std::int64_t triangles = 0;
  if (subdivision_level == 0) {
    for (const int n : control->face_sizes) triangles += n - 2;
  } else {
    triangles = 2 * corners;
    for (int level = 1; level < subdivision_level && triangles <= limits.max_surface_triangles; ++level) triangles *= 4;
  }
  if (triangles > limits.max_surface_triangles) {
    return make_error(413, file + ": its surface would have " + std::to_string(triangles) + " triangles or more; the limit is " +
                               std::to_string(limits.max_surface_triangles));
  }
  return Ok{};
}

}  // namespace cathbox::server
