#include "tool/aneurysm_sac.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include <glm/geometric.hpp>

namespace cathbox::tool {
namespace {

bool names_a_sac(const std::string& name) {
  std::string lower(name);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return lower.find("aneurysm") != std::string::npos;
}

glm::dvec3 d3(const glm::vec3& v) { return {v.x, v.y, v.z}; }

}  // namespace

double AneurysmSac::depth_mm(const glm::dvec3& p) const { return glm::dot(p - neck_centre_mm, neck_normal); }

double sphere_cap_volume_mm3(double radius_mm, double height_mm) {
  const double h = std::clamp(height_mm, 0.0, 2.0 * radius_mm);
  return M_PI * h * h * (3.0 * radius_mm - h) / 3.0;
}

std::optional<AneurysmSac> sphere_cap_sac(const glm::dvec3& dome_centre_mm, double dome_radius_mm,
                                          const glm::dvec3& neck_centre_mm) {
  const glm::dvec3 axis = dome_centre_mm - neck_centre_mm;
  const double d = glm::length(axis);
  if (!(dome_radius_mm > 0.0) || !(d > 1e-9) || !(d < dome_radius_mm)) return std::nullopt;
  AneurysmSac sac;
  sac.dome_centre_mm = dome_centre_mm;
  sac.dome_radius_mm = dome_radius_mm;
  sac.neck_centre_mm = neck_centre_mm;
  sac.neck_normal = axis / d;
  sac.neck_radius_mm = std::sqrt(dome_radius_mm * dome_radius_mm - d * d);
  sac.volume_mm3 = sphere_cap_volume_mm3(dome_radius_mm, dome_radius_mm + d);
  return sac;
}

double fan_closed_volume_mm3(std::span<const glm::vec3> positions, std::span<const std::uint32_t> triangles,
                             const glm::dvec3& apex_mm) {
  // Signed tetrahedra on the apex; the fan's own tetrahedra are flat (apex in the ring's plane).
  double six_v = 0.0;
  for (std::size_t i = 0; i + 2 < triangles.size(); i += 3) {
    const glm::dvec3 a = d3(positions[triangles[i]]) - apex_mm;
    const glm::dvec3 b = d3(positions[triangles[i + 1]]) - apex_mm;
    const glm::dvec3 c = d3(positions[triangles[i + 2]]) - apex_mm;
    six_v += glm::dot(a, glm::cross(b, c));
  }
  return six_v / 6.0;
}

std::optional<AneurysmSac> find_sac(const vessel::VesselModel& model, const vessel::SurfaceMesh& mesh) {
  const vessel::Segment* seg = nullptr;
  for (const vessel::Segment& s : model.segments) {
    if (names_a_sac(s.name) && s.points.size() >= 2) {
      seg = &s;
      break;
    }
  }
  if (seg == nullptr) return std::nullopt;
  // The sac's triangles (its tube and its end cap), their vertices welded by position (the
  // mesher may repeat a vertex where two regions meet).
  std::map<std::array<float, 3>, std::uint32_t> weld;
  std::vector<glm::vec3> pos;
  std::vector<std::uint32_t> tri;
  const auto id_of = [&](std::uint32_t v) {
    const glm::vec3 p = mesh.positions_mm[v];
    const auto [it, added] = weld.try_emplace({p.x, p.y, p.z}, static_cast<std::uint32_t>(pos.size()));
    if (added) pos.push_back(p);
    return it->second;
  };
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const vessel::FaceRegion r = mesh.triangle_regions[t];
    if (r.id != seg->id || (r.kind != vessel::RegionKind::kSegment && r.kind != vessel::RegionKind::kCap)) continue;
    for (int k = 0; k < 3; ++k) tri.push_back(id_of(mesh.triangles[3 * t + k]));
  }
  if (tri.empty()) return std::nullopt;
  // The open boundary: directed edges whose reverse no triangle holds.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (std::size_t i = 0; i < tri.size(); i += 3) {
    for (int k = 0; k < 3; ++k) ++edges[{tri[i + k], tri[i + (k + 1) % 3]}];
  }
  glm::dvec3 ring_sum(0.0);
  double ring_len = 0.0;
  std::vector<std::uint32_t> ring;
  for (const auto& [e, count] : edges) {
    if (edges.count({e.second, e.first}) != 0) continue;
    const glm::dvec3 a = d3(pos[e.first]);
    const glm::dvec3 b = d3(pos[e.second]);
    const double len = glm::length(b - a);
    ring_sum += 0.5 * (a + b) * len;
    ring_len += len;
    ring.push_back(e.first);
  }
  if (ring.size() < 3 || !(ring_len > 0.0)) return std::nullopt;
  const glm::dvec3 ring_centre = ring_sum / ring_len;
  const double surface_volume = fan_closed_volume_mm3(pos, tri, ring_centre);
  if (!(surface_volume > 0.0)) return std::nullopt;
  // The vessel mesher gives the first millimetres of the sac to the junction's patch: from the
  // neck (the segment's first centre-line point) to the ring the sac is the centre line's
  // frusta; from the ring on, the closed surface.
  AneurysmSac sac;
  sac.segment = seg->id;
  const vessel::CenterlinePoint& neck = seg->points.front();
  sac.neck_centre_mm = neck.pos_mm;
  sac.neck_radius_mm = neck.radius_mm;
  sac.neck_normal = glm::normalize(seg->points[1].pos_mm - neck.pos_mm);
  const double ring_at = arc_length_at(*seg, ring_centre);
  sac.volume_mm3 = surface_volume + frusta_volume_mm3(*seg, 0.0, ring_at);
  // Dome: the centroid of the surface part (tetrahedra on the ring's centre), and the radius of
  // the sphere of the sac's volume.
  glm::dvec3 moment(0.0);
  for (std::size_t i = 0; i < tri.size(); i += 3) {
    const glm::dvec3 a = d3(pos[tri[i]]), b = d3(pos[tri[i + 1]]), c = d3(pos[tri[i + 2]]);
    const double v = glm::dot(a - ring_centre, glm::cross(b - ring_centre, c - ring_centre)) / 6.0;
    moment += v * (a + b + c + ring_centre) / 4.0;
  }
  sac.dome_centre_mm = moment / surface_volume;
  sac.dome_radius_mm = std::cbrt(3.0 * sac.volume_mm3 / (4.0 * M_PI));
  return sac;
}

double frusta_volume_mm3(const vessel::Segment& sac, double from_mm, double to_mm) {
  double v = 0.0, s = 0.0;
  for (std::size_t i = 0; i + 1 < sac.points.size(); ++i) {
    const double h = glm::length(sac.points[i + 1].pos_mm - sac.points[i].pos_mm);
    const double lo = std::max(s, from_mm), hi = std::min(s + h, to_mm);
    if (hi > lo && h > 0.0) {
      const double r0 = sac.points[i].radius_mm, r1 = sac.points[i + 1].radius_mm;
      const double ra = r0 + (r1 - r0) * (lo - s) / h, rb = r0 + (r1 - r0) * (hi - s) / h;
      v += M_PI * (hi - lo) * (ra * ra + ra * rb + rb * rb) / 3.0;
    }
    s += h;
  }
  return v;
}

double arc_length_at(const vessel::Segment& sac, const glm::dvec3& p) {
  double best = std::numeric_limits<double>::max(), at = 0.0, s = 0.0;
  for (std::size_t i = 0; i + 1 < sac.points.size(); ++i) {
    const glm::dvec3 a = sac.points[i].pos_mm, ab = sac.points[i + 1].pos_mm - a;
    const double h2 = glm::dot(ab, ab);
    const double u = h2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / h2, 0.0, 1.0) : 0.0;
    const double d = glm::length(a + u * ab - p);
    if (d < best) best = d, at = s + u * std::sqrt(h2);
    s += std::sqrt(h2);
  }
  return at;
}

double centreline_sac_volume_mm3(const vessel::Segment& sac, double from_mm) {
  // The mesher closes a free end half a radius beyond it: a half spheroid (r, r, r/2).
  const double r = sac.points.empty() ? 0.0 : sac.points.back().radius_mm;
  return frusta_volume_mm3(sac, from_mm, std::numeric_limits<double>::max()) + 2.0 / 3.0 * M_PI * r * r * (0.5 * r);
}

}  // namespace cathbox::tool
