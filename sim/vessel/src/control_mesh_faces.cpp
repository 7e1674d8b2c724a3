// The control mesh's vertices and faces: each ring's vertices, the quad bands of the tubes, the
// end caps and the junction patches.
#include <cmath>

#include <glm/geometric.hpp>

#include "control_mesh_steps.hpp"
#include "junction_patch.hpp"

namespace cathbox::vessel::detail {
namespace {

constexpr double kCapOffsetRadii = 0.5;     // cap ring distance beyond the free end
constexpr double kCapRingScale = 0.6;       // cap ring radius / end ring radius

[[nodiscard]] std::string junction_name(const VesselModel& model, const Junction& junction, std::size_t index) {
  std::string out = "junction " + std::to_string(index) + " (segments";
  for (const SegmentEnd& e : junction.ends) out += " " + std::to_string(model.segments[e.segment].id);
  return out + ")";
}

}  // namespace

std::uint32_t ControlMeshBuilder::add_ring_vertices(const glm::dvec3& center, const glm::dvec3& normal, const glm::dvec3& binormal,
                                double radius) {
  const auto first = static_cast<std::uint32_t>(mesh_.positions_mm.size());
  for (std::size_t m = 0; m < ring_cos_.size(); ++m) {
    mesh_.positions_mm.push_back(center + radius * (ring_cos_[m] * normal + ring_sin_[m] * binormal));
  }
  return first;
}

void ControlMeshBuilder::emit_vertices() {
  mesh_.ring_points = m_;
  for (Ring& ring : mesh_.rings) {
    ring.first_vertex = add_ring_vertices(ring.center_mm, ring.normal, ring.binormal, ring.control_radius_mm);
  }
}

void ControlMeshBuilder::add_face(std::initializer_list<std::uint32_t> vertices, FaceRegion region) {
  mesh_.face_sizes.push_back(static_cast<int>(vertices.size()));
  for (std::uint32_t v : vertices) mesh_.face_vertices.push_back(static_cast<int>(v));
  mesh_.face_regions.push_back(region);
}

void ControlMeshBuilder::add_band(std::uint32_t a, std::uint32_t b, FaceRegion region) {
  const auto m_count = static_cast<std::uint32_t>(m_);
  for (std::uint32_t m = 0; m < m_count; ++m) {
    const std::uint32_t next = (m + 1) % m_count;
    add_face({a + m, a + next, b + next, b + m}, region);
  }
}

void ControlMeshBuilder::emit_tubes() {
  for (std::size_t s = 0; s < model_.segments.size(); ++s) {
    const FaceRegion region{RegionKind::kSegment, model_.segments[s].id};
    for (std::uint32_t r = mesh_.segment_first_ring[s]; r + 1 < mesh_.segment_first_ring[s + 1]; ++r) {
      add_band(mesh_.rings[r].first_vertex, mesh_.rings[r + 1].first_vertex, region);
    }
  }
}

void ControlMeshBuilder::emit_caps() {
  for (const SegmentEnd& e : graph_.free_ends()) {
    const Ring& ring = mesh_.rings[end_ring(e)];
    const glm::dvec3 out = e.at_end ? ring.tangent : -ring.tangent;
    const std::uint32_t extra =
        add_ring_vertices(ring.center_mm + out * (kCapOffsetRadii * ring.control_radius_mm), ring.normal,
                          ring.binormal, kCapRingScale * ring.control_radius_mm);
    const FaceRegion region{RegionKind::kCap, model_.segments[e.segment].id};
    if (e.at_end) add_band(ring.first_vertex, extra, region);
    else add_band(extra, ring.first_vertex, region);
    mesh_.face_sizes.push_back(m_);
    for (int m = 0; m < m_; ++m) {
      const int step = e.at_end ? m : (m_ - m) % m_;
      mesh_.face_vertices.push_back(static_cast<int>(extra) + step);
    }
    mesh_.face_regions.push_back(region);
  }
}

std::string ControlMeshBuilder::emit_junctions() {
  for (std::size_t j = 0; j < graph_.junctions().size(); ++j) {
    const Junction& junction = graph_.junctions()[j];
    std::vector<glm::dvec3> points;
    std::vector<detail::JunctionRing> rings;
    std::vector<detail::JunctionRingFrame> frames;
    std::vector<std::uint32_t> first_vertex;
    for (const SegmentEnd& e : junction.ends) {
      const Ring& ring = mesh_.rings[end_ring(e)];
      rings.push_back({!e.at_end});
      frames.push_back({e.at_end ? -ring.tangent : ring.tangent, ring.normal, ring.binormal, ring.center_mm});
      first_vertex.push_back(ring.first_vertex);
      for (int m = 0; m < m_; ++m) points.push_back(mesh_.positions_mm[ring.first_vertex + static_cast<std::uint32_t>(m)]);
    }
    detail::JunctionPatchResult patch = detail::build_junction_patch(points, rings, m_);
    if (!patch.error.empty() && options_.junction_fallback) {
      std::string what = junction_name(model_, junction, j) + ": " + patch.error;
      patch = detail::build_spherical_junction_patch(points, rings, frames, m_);
      if (patch.error.empty()) mesh_.fallback_junctions.push_back({static_cast<std::uint32_t>(j), std::move(what)});
    }
    if (!patch.error.empty()) return junction_name(model_, junction, j) + ": " + patch.error;
    const FaceRegion region{RegionKind::kJunction, static_cast<std::int32_t>(j)};
    for (const std::vector<int>& face : patch.faces) {
      mesh_.face_sizes.push_back(static_cast<int>(face.size()));
      for (int local : face) {
        mesh_.face_vertices.push_back(static_cast<int>(first_vertex[static_cast<std::size_t>(local / m_)]) +
                                      local % m_);
      }
      mesh_.face_regions.push_back(region);
    }
  }
  return {};
}

}  // namespace cathbox::vessel::detail
