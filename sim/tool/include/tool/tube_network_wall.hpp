#pragma once
// An analytic lumen: the union of tapered tubes (capsules) around centreline segments. Used for
// validation (straight tube, circular bend, Y bifurcation) and as a light lumen built straight
// from a central axis model. A uniform grid finds the candidate tubes near a point.
#include <cstdint>
#include <vector>

#include "tool/wall_model.hpp"

namespace cathbox::tool {

struct Tube {
  glm::dvec3 a_mm{0.0};
  glm::dvec3 b_mm{0.0};
  double radius_a_mm = 1.0;
  double radius_b_mm = 1.0;
  std::int32_t segment = 0;
};

class TubeNetworkWall final : public WallModel {
 public:
  TubeNetworkWall() = default;
  explicit TubeNetworkWall(std::vector<Tube> tubes, double cell_mm = 0.0);

  // A polyline tube (e.g. a circular bend sampled finely) with one radius.
  void add_polyline(const std::vector<glm::dvec3>& points_mm, double radius_mm, std::int32_t segment);
  void add_tube(const Tube& tube);
  // Builds the grid; call after the last add_*.
  void build(double cell_mm = 0.0);

  [[nodiscard]] bool probe(const WallProbe& probe, WallHint& hint, WallContact& out) const override;
  // The radii of the tubes holding the point, at their axis points, blended (LumenBlend).
  [[nodiscard]] double lumen_radius_mm(const glm::dvec3& point_mm) const override;
  // Signed distance of a point to the wall (positive inside the lumen) and the tube holding it.
  [[nodiscard]] double signed_distance(const glm::dvec3& p_mm, std::int32_t* segment = nullptr) const;
  [[nodiscard]] const std::vector<Tube>& tubes() const { return tubes_; }

 private:
  // Depth of p inside tube i (positive inside) and the closest axis point / radius.
  [[nodiscard]] double depth_in(std::size_t i, const glm::dvec3& p, glm::dvec3& axis_point) const;
  [[nodiscard]] bool closest(const glm::dvec3& p, bool use_grid, WallContact& out) const;
  // The tube p lies deepest in (its index, axis point and depth); -inf depth when none.
  [[nodiscard]] double deepest(const glm::dvec3& p, bool use_grid, std::size_t& best_i, glm::dvec3& best_axis) const;
  [[nodiscard]] std::int64_t cell_of(const glm::dvec3& p) const;
  // Calls fn(i) for each tube that may hold p: the grid cell's, else every tube.
  template <typename Fn>
  void for_candidates(const glm::dvec3& p, bool use_grid, Fn&& fn) const;

  std::vector<Tube> tubes_;
  glm::dvec3 origin_{0.0};
  double cell_ = 1.0;
  std::int64_t nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<std::uint32_t> cell_start_;  // CSR: candidates of cell c in [start[c], start[c+1])
  std::vector<std::uint32_t> cell_items_;
  double reach_ = 0.0;                     // grid inflation (max query range + radius)
};

}  // namespace cathbox::tool
