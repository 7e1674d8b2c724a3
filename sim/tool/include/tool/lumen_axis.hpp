#pragma once
// The lumen as the tubes round its centrelines (the vessel model a meshed wall was built from):
// for a point, the union of the segments' tubes, each the centreline polyline swept by its
// radius (linear along each piece). Its clearance, max over the segments of R(foot) − |x − foot|,
// is continuous and, away from junctions and the inside of bends, smooth: what an expanded
// stent node, as wide as its lumen, is held by instead of the mesh's facets (whose planes it
// flips between from one Newton iteration to the next). Coherent: a per-node hint (segment and
// piece) climbs along the segment and looks into the neighbours at a junction; a full scan of
// the model when the hint is new or the point has moved kRescan_mm since the last one.
#include <cstdint>
#include <vector>

#include "tool/wall_model.hpp"

namespace cathbox::tool {

struct AxisHint {
  std::int32_t segment = -1;  // index into the model's segments; -1: none yet
  std::uint32_t piece = 0;
  glm::dvec3 scanned_at_mm{0.0};
};

class LumenAxis {
 public:
  static constexpr double kRescan_mm = 3.0;
  // `model` must outlive this (the wall's shared surface holds it).
  explicit LumenAxis(const vessel::VesselModel& model);
  // The union of the tubes meeting at a junction is smoothed over about this much (a soft
  // maximum of their clearances): its inner corner, a crease that would catch a node dragged
  // round it, is rounded as the surface's blend of the segments is.
  static constexpr double kBlend_mm = 0.6;
  enum class Answer { kClear, kWall, kNone };
  // As WallModel::probe: the wall point, outward normal and signed clearance of the centre;
  // kWall when the node's surface is within probe.range_mm of the wall (or outside the lumen),
  // kClear when not, kNone (out unset) for a model without points.
  [[nodiscard]] Answer probe(const WallProbe& probe, AxisHint& hint, WallContact& out) const;

 private:
  struct Foot {
    double value = -1e300;  // R(foot) - distance: the clearance this segment's tube gives
    std::int32_t segment = -1;
    std::uint32_t piece = 0;
    glm::dvec3 foot_mm{0.0};
    double radius_mm = 0.0;
  };
  struct Neighbour {
    std::int32_t segment;
    bool from_start;  // climb from its first piece (else its last)
  };
  [[nodiscard]] Foot on_piece(std::int32_t s, std::uint32_t piece, const glm::dvec3& p) const;
  [[nodiscard]] Foot climb(std::int32_t s, std::uint32_t piece, const glm::dvec3& p) const;
  [[nodiscard]] Foot scan(const glm::dvec3& p) const;
  [[nodiscard]] std::uint32_t pieces(std::int32_t s) const;

  [[nodiscard]] glm::dvec3 outward(const Foot& f, const glm::dvec3& p) const;
  static constexpr std::size_t kMostNear = 8;

  const vessel::VesselModel& model_;
  std::vector<std::vector<Neighbour>> at_start_, at_end_;  // per segment index
};

}  // namespace cathbox::tool
