#pragma once
// A vessel wall moved radially by a displacement field, read by the queries: the wall as the
// solver sees it is the exact wall (a collision tree or analytic tubes, never refit) offset
// along its outward normal by the displacement of the segment the wall point belongs to. For a
// uniform offset of every segment the result is exact (the offset of a union of tubes is the
// union of the offset tubes; a mesh's closest point and normal are those of its offset surface
// wherever the offset keeps the closest face); per segment it is exact away from junctions,
// which take `junction_mm`. What moves it: the pulse (`WallShell`, Laplace distension under the
// flow's pressure), set by the caller each tick; nothing here allocates per query.
#include <cstdint>
#include <vector>

#include "tool/wall_model.hpp"

namespace cathbox::tool {

class DisplacedWall final : public WallModel {
 public:
  explicit DisplacedWall(const WallModel& inner) : inner_(inner) {}

  // Radial displacement (mm, outward positive; > -radius) of every wall point.
  void set_uniform_mm(double w_mm);
  // Of the wall points of one segment (ids >= 0), over the uniform value.
  void set_segment_mm(std::int32_t segment, double w_mm);
  [[nodiscard]] double displacement_mm(std::int32_t segment) const;

  [[nodiscard]] bool probe(const WallProbe& probe, WallHint& hint, WallContact& out) const override;
  [[nodiscard]] std::shared_ptr<const WallSurface> surface() const override { return inner_.surface(); }
  [[nodiscard]] std::uint64_t revision() const override { return revision_; }
  [[nodiscard]] double lumen_radius_mm(const glm::dvec3& point_mm) const override {
    const double r = inner_.lumen_radius_mm(point_mm);
    return r > 0.0 ? r + uniform_mm_ : r;
  }

 private:
  const WallModel& inner_;
  double uniform_mm_ = 0.0;
  double largest_mm_ = 0.0;  // the largest outward displacement of any segment (query range)
  std::vector<double> segment_mm_;
  std::vector<std::uint8_t> segment_set_;
  std::uint64_t revision_ = 0;  // raised by every set_* that moves a wall point
};

}  // namespace cathbox::tool
