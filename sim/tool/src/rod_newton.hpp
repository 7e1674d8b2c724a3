#pragma once
// Private to the rod's sources: what the Newton solve of one step carries from phase to phase
// (rod_newton.cpp), and the adder of 3x3 blocks to the rod's banded system in either order.
#include <cstddef>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>

#include "tool/banded_cholesky.hpp"
#include "tool/rod.hpp"

namespace cathbox::tool {

struct Rod::Newton {
  Newton(const WallModel& wall_model, const RodObstacles* other_rods) : wall(wall_model), obstacles(other_rods) {}
  const WallModel& wall;
  const RodObstacles* obstacles;  // nullptr: no other rods
  std::size_t dofs = 0;           // unknowns of the simulated window, 3 per node
  std::size_t free0 = 0;          // first unknown of a free node
  int iterations = 0;             // RodSettings::newton_iterations, at least 1
  int rounds = 0;                 // iterations allowed, raised by up to two to hold joining nodes
  int activations = 0;            // rounds that solved again with nodes joined to the active set
  // The Hessian is assembled and factored again only when the active set or an active contact
  // plane changed, or a step failed to lower the energy; otherwise only the gradient is rebuilt
  // (chord iterations).
  bool refactor = true;
  bool rejoin = false;   // amend the assembly with the wall terms of the nodes that joined
  std::size_t rejoin_from = 0;  // first node whose wall terms the rejoin amended; node count: none
  bool stepped = false;  // last_step_ holds an update of this step
  // This iteration's.
  bool fresh = false;    // the factorisation is of this iteration's assembly
  double largest = 0.0;  // the largest node update of the Newton step
  double scale = 1.0;    // the fraction of the Newton step taken
  double aim = 1.0;      // the fraction of the Newton step the iteration means to take
  bool entered = false;  // a node the step carried into the wall is deeper than 1 % of the limit
  bool deep = false;     // a held node is past the penetration limit
  double released_pull_mN = 0.0;  // the largest pull of the wall on a node the active set let go
};

inline void Rod::add_grad(std::size_t k, const glm::dvec3& g) {
  const std::size_t d = 3 * (k - first_);
  grad_[d] += g.x;
  grad_[d + 1] += g.y;
  grad_[d + 2] += g.z;
}

// Bending residual on the unit tangents around vertex i: r = t_b - t_a - (rest turn towards
// m1). |t_b - t_a| is 2 sin(phi/2) of the turning angle phi: the discrete curvature for small
// angles, and bounded for kinks, which keeps the Gauss-Newton steps good. Inline: the assembly,
// the energy and the twist call it per vertex.
[[gnu::always_inline]] inline glm::dvec3 Rod::bend_residual(std::size_t i, const glm::dvec3& ta, const glm::dvec3& tb) const {
  glm::dvec3 r = tb - ta;
  if (kturn1_[i] == 0.0 && kturn2_[i] == 0.0) return r;
  // The clamp vertex and the first free node bend over lengths of their own (update_weights).
  const double scale = turn_scale(i);
  if (kturn1_[i] != 0.0) r -= (m1_[i - 1] + m1_[i]) * (0.5 * kturn1_[i] * scale);
  if (kturn2_[i] != 0.0) r -= (m2_[i - 1] + m2_[i]) * (0.5 * kturn2_[i] * scale);
  return r;
}

namespace rod_detail {

// Adds a 3x3 block to the rod's banded system at nodes (a, b) in either order (the system keeps
// its lower half), the window starting at node `first`; nothing when not enabled.
struct BlockAdder {
  BandedCholesky& m;
  std::size_t first;
  bool enabled;
  void operator()(std::size_t a, std::size_t b, const glm::dmat3& block) const {
    if (!enabled) return;
    if (a < b) {
      m.add_block(b - first, a - first, glm::transpose(block));
      return;
    }
    m.add_block(a - first, b - first, block);
  }
};

}  // namespace rod_detail
}  // namespace cathbox::tool
