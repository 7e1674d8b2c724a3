#pragma once
// A rod's contacts: the planes another rod (or another part of itself) holds it by, the
// obstacles that gather them, and a node's wall contact as the rod reports it (rod.hpp).
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace cathbox::tool {

class Rod;

// One side of a contact between two rods, or between two parts of one rod, as the rod being
// solved sees it: the point p = (1 - s) x[edge] + s x[edge + 1] must stay on the positive side
// of the plane normal . p >= offset_mm. The planes are taken when gathered and held for the
// iterations that follow (the other side is frozen, or, for two parts of the same rod, each
// side is held to its half of the gap); penetration is penalised quadratically.
struct EdgeContact {
  std::uint32_t edge = 0;
  double s = 0.0;
  glm::dvec3 normal{0.0};
  double offset_mm = 0.0;
  double force_mN = 0.0;  // after the step: the contact force along the normal
  double stiffness_mN_per_mm = 0.0;  // > 0: this contact's penalty stiffness, not the rod's own
};

// The penalty stiffness of a contact: its own if set (a balloon's side takes the coil's law),
// else the rod's `rod_kc`. Every term of a plane (energy, gradient, Hessian, the predicted step,
// the force read after the step) uses this one.
inline double edge_stiffness(const EdgeContact& ec, double rod_kc) {
  return ec.stiffness_mN_per_mm > 0.0 ? ec.stiffness_mN_per_mm : rod_kc;
}

// Rods (and the rod itself, away from its neighbours along it) a rod must not pass through.
class RodObstacles {
 public:
  virtual ~RodObstacles() = default;
  // Replaces `out` with the contact planes of `rod` at its present positions.
  virtual void gather(const Rod& rod, std::vector<EdgeContact>& out) const = 0;
  // Pairs closer than the contact distance plus this margin are gathered; a node may move
  // half of it before the planes are gathered again.
  [[nodiscard]] virtual double margin_mm() const = 0;
};

struct RodContact {
  std::uint32_t node = 0;
  glm::dvec3 point_mm{0.0};      // wall point
  glm::dvec3 normal{0.0};        // unit, out of the lumen
  double normal_force_mN = 0.0;  // wall on the tool, along -normal
  glm::dvec3 friction_mN{0.0};   // wall friction on the tool
  std::int32_t segment = -1;
};

}  // namespace cathbox::tool
