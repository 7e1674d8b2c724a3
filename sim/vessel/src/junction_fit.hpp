#pragma once
// Fits the surface of long junction patches to the tubes of their branches.
//
// A junction patch is the convex hull of the rings that meet there, and the rings must be pulled
// back until each lies behind every other ring's plane: ~2.5 radii at 60 degrees between two
// branches, ~10 at 18 degrees (the vertebral arteries into the basilar). A handful of hull faces
// then span the stretch where the branches run side by side, and their limit surface is 5-10 %
// wider than the branches there (or, at narrow angles, pinches one of them).
//
// At every junction where a ring sits further than kFitTrimRadii of its radius from the junction
// end, the vertices of the refinement level before the last (L-1) that descend from the patch's
// faces get a target: their Catmull-Clark limit position moved radially onto the tube of the
// branch it is nearest to (the branch's smoothed centreline, Catmull-Rom between points, radius
// linear between points). The move is weighted: smoothstep((|d2| - |d1|) / (kFitBlendRadii r1)),
// d1 and d2 the signed distances to the nearest and second nearest tube surface, or 1 where the
// point is outside both and they lie on the same side of it (above two branches running side by
// side), times a fade for points further than kFitFullRadii..kFitMaxMoveRadii from every tube; a
// point inside another branch's tube (the lumen the branches share) does not move. So the crotch and the hull's
// bridge between branches that have parted stay as they are, and a branch's outer side lands on
// its tube. The tube's own vertices up to kFitTubeFadeRadii beyond the ring follow with a weight
// fading to 0, so the fitted patch joins the tube smoothly. The vertices are then moved
// (kFitIterations Richardson steps, v += target - limit(v)) until their limit positions reach
// the targets. Where the weight falls off next to a vertex its limit can only follow by the
// vertex moving ~2.25 times as far, which may fold the faces around it: the vertices of a face
// that turned by more than kFitMaxTurn_deg have their moves halved (up to kFitUnfoldSteps times). Doing this one level before the last keeps the limit surface smooth and its
// normals exact, at a quarter of the vertices of the last level.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "vessel/control_mesh.hpp"
#include "vessel/subdivision.hpp"
#include "vessel/vessel_graph.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::vessel::detail {

constexpr double kFitTrimRadii = 1.5;      // a junction is fitted when a ring is further out than this
constexpr double kFitBlendRadii = 0.5;     // d2 - d1 over which the move fades in
constexpr double kFitFullRadii = 0.3;      // vertices this near their tube (in its radii) move all the way,
constexpr double kFitMaxMoveRadii = 0.6;   // those further than this not at all (fading in between)
constexpr double kFitTubeFadeRadii = 1.5;  // beyond the ring, the tube's vertices follow over this
constexpr double kFitSameSide = 0.5;       // cosine above which two tubes' directions count as the same side
constexpr double kFitInsideRadii = 0.1;    // deeper than this inside another branch's tube: not moved
constexpr int kFitIterations = 4;          // steps moving the vertices until their limits reach the targets
constexpr double kFitMaxTurn_deg = 45.0;    // a level L-1 face turned further than this by the fit ...
constexpr int kFitUnfoldSteps = 4;         // ... has its vertices' moves halved, at most this often

struct JunctionFitReport {
  std::size_t junctions = 0;  // junctions fitted
  std::size_t vertices = 0;   // level L-1 vertices with a target
  double max_move_mm = 0.0;
};

class JunctionFit {
 public:
  // `smoothed`, `graph` and `control` are what the surface is built from.
  JunctionFit(const VesselModel& smoothed, const VesselGraph& graph, const ControlMesh& control);

  // True when no junction needs fitting (the surface is then built without a LevelAdjuster).
  [[nodiscard]] bool empty() const { return junctions_.empty(); }

  // Moves the vertices of `level` (the level before the last) as described above.
  void apply(RefinedLevel& level);

  [[nodiscard]] const JunctionFitReport& report() const { return report_; }

  // The part of one branch's axis near the junction, from the junction end outward.
  struct Axis {
    std::vector<glm::dvec3> pos;
    std::vector<double> radius;
    double step = 0.0;        // between samples, mm
    double trim = 0.0;        // arc of the branch's ring from the junction end
    double ring_radius = 0.0;
    std::vector<std::uint32_t> fade_faces;  // tube control faces within kFitTubeFadeRadii beyond the ring
    glm::dvec3 bound_center{0.0};           // a sphere holding every sample
    double bound_radius = 0.0;
    double max_radius = 0.0;                // the largest tube radius along it
  };
  struct FittedJunction {
    std::vector<Axis> axes;                  // one per branch
    std::vector<std::uint32_t> patch_faces;  // its control faces
  };

 private:
  const ControlMesh& control_;
  std::vector<FittedJunction> junctions_;
  JunctionFitReport report_;
};

}  // namespace cathbox::vessel::detail
