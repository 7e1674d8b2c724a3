#include "lumen_regions.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <unordered_map>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/type_precision.hpp>

namespace cathbox::vessel_import {
namespace {

// The centreline points of a model in a grid of cells as wide as its widest radius, for the
// nearest segment to a point (searched outward ring by ring).
class CentrelineGrid {
 public:
  explicit CentrelineGrid(const vessel::VesselModel& model) {
    for (const vessel::Segment& s : model.segments) {
      for (const vessel::CenterlinePoint& p : s.points) cell_ = std::max(cell_, p.radius_mm);
    }
    for (const vessel::Segment& s : model.segments) {
      for (const vessel::CenterlinePoint& p : s.points) cells_[hash(key(p.pos_mm))].push_back({p.pos_mm, s.id});
    }
    fallback_ = model.segments.empty() ? 0 : model.segments.front().id;
  }
  [[nodiscard]] bool usable() const { return cell_ > 0.0; }

  [[nodiscard]] std::int32_t nearest_segment(const glm::dvec3& c) const {
    Best best{std::numeric_limits<double>::infinity(), fallback_};
    const glm::i64vec3 home = key(c);
    for (std::int64_t ring = 0; ring < 64; ++ring) {
      visit_ring(home, ring, c, best);
      if (best.distance <= static_cast<double>(ring) * cell_) break;  // no farther ring is nearer
    }
    return best.id;
  }

 private:
  struct Entry {
    glm::dvec3 pos;
    std::int32_t id;
  };
  struct Best {
    double distance;
    std::int32_t id;
  };
  [[nodiscard]] glm::i64vec3 key(const glm::dvec3& p) const {
    return glm::i64vec3(std::floor(p.x / cell_), std::floor(p.y / cell_), std::floor(p.z / cell_));
  }
  [[nodiscard]] static std::size_t hash(const glm::i64vec3& k) {
    return static_cast<std::size_t>((k.x * 73856093) ^ (k.y * 19349663) ^ (k.z * 83492791));
  }
  // The cells on the surface of the cube `ring` cells out from `home`.
  void visit_ring(const glm::i64vec3& home, std::int64_t ring, const glm::dvec3& c, Best& best) const {
    for (std::int64_t dx = -ring; dx <= ring; ++dx) {
      for (std::int64_t dy = -ring; dy <= ring; ++dy) {
        for (std::int64_t dz = -ring; dz <= ring; ++dz) {
          if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) == ring) visit_cell(home + glm::i64vec3(dx, dy, dz), c, best);
        }
      }
    }
  }
  void visit_cell(const glm::i64vec3& k, const glm::dvec3& c, Best& best) const {
    const auto it = cells_.find(hash(k));
    if (it == cells_.end()) return;
    for (const Entry& e : it->second) {
      const double d = glm::length(e.pos - c);
      if (d < best.distance) best = {d, e.id};
    }
  }

  double cell_ = 0.0;
  std::int32_t fallback_ = 0;
  std::unordered_map<std::size_t, std::vector<Entry>> cells_;
};

}  // namespace

// Each lumen triangle takes the segment whose centreline point is nearest its centroid.
void tag_lumen_regions(const vessel::VesselModel& model, vessel::SurfaceMesh& lumen) {
  const CentrelineGrid grid(model);
  if (!grid.usable()) return;
  for (std::size_t t = 0; t < lumen.triangle_count(); ++t) {
    const glm::dvec3 c = (glm::dvec3(lumen.positions_mm[lumen.triangles[3 * t]]) +
                          glm::dvec3(lumen.positions_mm[lumen.triangles[3 * t + 1]]) +
                          glm::dvec3(lumen.positions_mm[lumen.triangles[3 * t + 2]])) / 3.0;
    lumen.triangle_regions[t] = {vessel::RegionKind::kSegment, grid.nearest_segment(c)};
  }
}

}  // namespace cathbox::vessel_import
