#pragma once
// Private to the rod's sources: the state a step starts from, kept so that a tick whose solve
// ended unconverged can be solved again in sub-increments (rod_substep.cpp). Nodes below the
// simulated window are left out: they sit on the entry line and enter it afresh.
#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "rod_node_contact.hpp"
#include "tool/rod.hpp"

namespace cathbox::tool {

struct Rod::StepStart {
  std::size_t from = 0;  // first node kept (the window's first at the step's start)
  std::vector<glm::dvec3> x, grip_anchor, solved_move, gathered_at;
  std::vector<NodeContact> node_contacts;
  std::vector<double> grip_limit;
  std::vector<std::uint8_t> tw_regime;
  // Per edge (and ref_twist_ per vertex), from the same first node.
  std::vector<double> theta, ref_twist;
  std::vector<glm::dvec3> t, d1, m1, m2;
  std::vector<RodContact> contacts;
  std::vector<EdgeContact> edge_contacts;
  std::size_t first = 0, first_free = 0, warm_first = 0;
  double stepped_insertion_mm = 0.0;
  double stepped_rotation_rad = 0.0;
  bool compressed = false;
  bool warm_ok = false;
};

}  // namespace cathbox::tool
