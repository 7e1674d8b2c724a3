#pragma once
// The wall a tool node can touch, as the rod solver sees it: for a node (centre, radius) the
// closest wall point, the wall's outward normal there and the signed clearance of the centre.
// Analytic walls (tubes, bends, bifurcations) and the vessel mesh (through the collision tree)
// implement it.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "vessel/surface_mesh.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::tool {

struct WallProbe {
  glm::dvec3 center_mm{0.0};
  double radius_mm = 0.0;
  double range_mm = 2.0;     // report the wall only if the node surface is within this distance
  double margin_mm = 0.15;   // a second touching wall is looked for within this distance
  // False: the closest wall alone, no second wall (a node as wide as its lumen, an expanded
  // stent's: it touches the whole ring, and every facet would be a "second wall").
  bool second_wall = true;
  // True: the lumen as the tubes round its centrelines (LumenAxis), where the wall was built
  // from a vessel model (a meshed wall); ignored by the analytic walls, which are tubes already.
  // For an expanded stent node: smooth and convex where the mesh's facets are not.
  bool lumen_axis = false;
  double depth_mm = 0.0;     // how far past the entry this node is along its tool (coaxial walls use it)
};

struct WallContact {
  glm::dvec3 point_mm{0.0};  // closest wall point
  glm::dvec3 normal{0.0};    // unit, pointing out of the lumen into the wall
  double distance_mm = 0.0;  // signed distance of the centre to the wall, positive inside the lumen
  std::int32_t segment = -1; // vessel segment (or analytic tube) the wall point belongs to
  // A second wall the node touches at the same time (a crease of a meshed wall, where one
  // plane alone would let the node slip into the neighbouring face).
  bool has_second = false;
  glm::dvec3 second_point_mm{0.0};
  glm::dvec3 second_normal{0.0};
};

// Per-node memory a wall may use to answer the next query faster (coherent queries).
struct WallHint {
  std::uint32_t index = 0xffffffffu;
};

// The hint pool the calling thread's probes take their slots from: 0, the haptic thread's; 1,
// the thread that solves the released coils beside it (Simulator, background_job.hpp). A wall
// that keeps per-slot state (MeshWall) keeps each pool's slots apart, so two threads probing at
// once never share one (a slot only speeds its node's queries up: MeshWall). Set for a scope.
inline constexpr int kProbePools = 2;
[[nodiscard]] int probe_pool();
class ProbePoolScope {
 public:
  explicit ProbePoolScope(int pool);
  ~ProbePoolScope();
  ProbePoolScope(const ProbePoolScope&) = delete;
  ProbePoolScope& operator=(const ProbePoolScope&) = delete;

 private:
  int before_;
};

// What a meshed wall was built from, for those who draw it (renderers): the lumen's central-axis
// model (the HCLM radii, widened by a balloon) and the surface meshed from it. Immutable; shared.
struct WallSurface {
  vessel::VesselModel model;
  vessel::SurfaceMesh mesh;
};

class WallModel {
 public:
  virtual ~WallModel() = default;
  // The surface this wall was built from; empty for analytic walls.
  [[nodiscard]] virtual std::shared_ptr<const WallSurface> surface() const { return {}; }
  // Fills `out` and returns true when the wall is within probe.range_mm of the node surface
  // (or the node is outside the lumen); returns false otherwise.
  [[nodiscard]] virtual bool probe(const WallProbe& probe, WallHint& hint, WallContact& out) const = 0;
  // The lumen's radius at a point inside it: the analytic tubes' there, else the centrelines' of
  // the surface's model (centreline_radius_mm: a scan of its points, for events and occasional
  // reads, not every node every step); continuous across junctions (LumenBlend); negative when
  // the wall cannot tell.
  [[nodiscard]] virtual double lumen_radius_mm(const glm::dvec3& point_mm) const;
  // Counts the changes of a wall that moves in place (a displaced wall's pulse): a rod at rest
  // against it must be solved again when it changes. 0 for a wall that never moves.
  [[nodiscard]] virtual std::uint64_t revision() const { return 0; }
};

// The nearest point of a segment's centreline to a point: its squared distance, the piece
// (points i and i + 1; 0 for a one-point segment) and the fraction along it.
struct CentrelineFoot {
  double distance2_mm2 = 0.0;
  std::size_t piece = 0;
  double t = 0.0;
};
[[nodiscard]] CentrelineFoot nearest_on_centreline(const vessel::Segment& s, const glm::dvec3& point_mm);
// The lumen's radius at a point from the tubes (or centrelines) that may hold it, each given as
// its radius at the point's foot on its axis and the point's depth in it (that radius minus the
// distance to the axis). The deepest tube alone would make the read jump where the deepest
// changes (a junction, where a branch of another radius takes over; the joint of two pieces):
// each tube weighs max(0, d - D + h)^2, d its depth, D the deepest, h = max(D, kBand_mm), so a
// tube's weight rises from 0 as it comes within h of the deepest and the read is continuous.
// A point in one tube alone (every other more than h shallower) reads that tube's radius exactly.
class LumenBlend {
 public:
  static constexpr double kBand_mm = 0.1;  // the blend's least width, for points near the wall
  void add(double depth_mm, double radius_mm);
  // The blended radius; negative when no tube was added.
  [[nodiscard]] double radius_mm() const;

 private:
  // Held in place (a read runs in the haptic step: a stent node's regauge), past kHeld in more_.
  // A tube shallower than the deepest so far by its band or more weighs 0 now and at every
  // deeper D (D - max(D, band) never falls), so it is not kept.
  static constexpr std::size_t kHeld = 32;
  struct Held {
    double depth_mm;
    double radius_mm;
  };
  [[nodiscard]] double floor_mm() const { return deepest_mm_ - std::max(deepest_mm_, kBand_mm); }
  std::array<Held, kHeld> held_{};
  std::size_t count_ = 0;
  std::vector<Held> more_;  // once held_ is full of tubes that still weigh
  double deepest_mm_ = -std::numeric_limits<double>::infinity();
  bool added_ = false;
};

// The lumen's radius at a point of a model's centrelines: the radii at the nearest point of each
// segment's centreline (linear along each piece), blended by LumenBlend.
[[nodiscard]] double centreline_radius_mm(const vessel::VesselModel& model, const glm::dvec3& point_mm);

}  // namespace cathbox::tool
