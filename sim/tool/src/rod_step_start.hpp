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
  // Not the rod-rod planes (edge_contacts_): step_once clears them before anything reads them
  // (begin_step does not), so a copy put back is never read; it was ~1 % of the coil packing
  // bench's instructions, every step of every rod.
  std::size_t first = 0, first_free = 0, warm_first = 0;
  double stepped_insertion_mm = 0.0;
  double stepped_rotation_rad = 0.0;
  bool compressed = false;
  bool jammed = false;
  bool warm_ok = false;

  // Each kept field beside the rod's own: per_node(kept, live) for the window's per-node and
  // per-edge vectors (from `from` on), whole(kept, live) for the rest. Saving and restoring walk
  // the same list, so a field added here is both kept and put back.
  template <typename PerNode, typename Whole>
  void pair_with(Rod& rod, PerNode&& per_node, Whole&& whole) {
    per_node(x, rod.x_);
    per_node(grip_anchor, rod.grip_anchor_);
    per_node(grip_limit, rod.grip_limit_);
    per_node(solved_move, rod.solved_move_);
    per_node(gathered_at, rod.gathered_at_);
    per_node(node_contacts, rod.node_contacts_);
    per_node(tw_regime, rod.tw_regime_);
    per_node(theta, rod.theta_);
    per_node(ref_twist, rod.ref_twist_);
    per_node(t, rod.t_);
    per_node(d1, rod.d1_);
    per_node(m1, rod.m1_);
    per_node(m2, rod.m2_);
    whole(contacts, rod.contacts_);
    whole(first, rod.first_);
    whole(first_free, rod.first_free_);
    whole(warm_first, rod.warm_first_);
    whole(stepped_insertion_mm, rod.stepped_insertion_mm_);
    whole(stepped_rotation_rad, rod.stepped_rotation_rad_);
    whole(compressed, rod.compressed_);
    whole(jammed, rod.jammed_);
    whole(warm_ok, rod.warm_ok_);
  }
};

}  // namespace cathbox::tool
