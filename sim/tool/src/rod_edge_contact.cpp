// Contacts with other rods and with the rod's own far parts (coil loops): the planes gathered
// from RodObstacles, their one-sided penalty in the solve, and the projection of the nodes
// still past the penetration limit after it.
#include <algorithm>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "rod_newton.hpp"
#include "rod_node_contact.hpp"
#include "tool/rod.hpp"

namespace cathbox::tool {

void Rod::gather_obstacles(const RodObstacles& obstacles) {
  obstacles.gather(*this, edge_contacts_);
  for (std::size_t k = first_free_; k < x_.size(); ++k) gathered_at_[k] = x_[k];
  // Only edges with a free node can move away.
  std::erase_if(edge_contacts_, [&](const EdgeContact& c) {
    return c.edge + 1 >= x_.size() || c.edge + 1 < first_free_;
  });
}

bool Rod::moved_since_gather(double limit_mm) const {
  const double limit_sq = limit_mm * limit_mm;
  for (std::size_t k = first_free_; k < x_.size(); ++k) {
    const glm::dvec3 d = x_[k] - gathered_at_[k];
    if (glm::dot(d, d) > limit_sq) return true;
  }
  return false;
}

// Other rods (and the rod's own far parts): one-sided penalty on the gathered planes.
void Rod::add_edge_contact_terms(bool hessian) {
  const double kc_rod = settings_.contact_stiffness_mN_per_mm;
  const rod_detail::BlockAdder add{*matrix_, first_, hessian};
  for (const EdgeContact& ec : edge_contacts_) {
    const double phi = edge_gap(ec);
    if (phi <= 0.0) continue;
    const double kc = ec.stiffness_mN_per_mm > 0.0 ? ec.stiffness_mN_per_mm : kc_rod;
    const std::size_t a = ec.edge;
    const double wa = 1.0 - ec.s;
    const double wb = ec.s;
    energy_ += 0.5 * kc * phi * phi;
    if (a >= first_free_) add_grad(a, -ec.normal * (kc * phi * wa));
    if (a + 1 >= first_free_) add_grad(a + 1, -ec.normal * (kc * phi * wb));
    if (!hessian) continue;
    const glm::dmat3 nn = kc * glm::outerProduct(ec.normal, ec.normal);
    if (a >= first_free_) add(a, a, nn * (wa * wa));
    if (a + 1 >= first_free_) add(a + 1, a + 1, nn * (wb * wb));
    if (a >= first_free_) add(a + 1, a, nn * (wa * wb));
  }
}

bool Rod::finish_edge_contacts() {
  // Held to within the penetration limit, like the wall; the force is the penalty's.
  const double kc_rod = settings_.contact_stiffness_mN_per_mm;
  bool pushed = false;
  for (EdgeContact& ec : edge_contacts_) {
    const double phi = edge_gap(ec);
    const double allowed = settings_.max_penetration_ratio * radius_[ec.edge];
    if (phi > allowed) {
      pushed = true;
      const glm::dvec3 push = ec.normal * (phi - allowed);
      if (ec.edge >= first_free_) x_[ec.edge] += push;
      if (ec.edge + 1 >= first_free_) x_[ec.edge + 1] += push;
    }
    const double kc = ec.stiffness_mN_per_mm > 0.0 ? ec.stiffness_mN_per_mm : kc_rod;
    ec.force_mN = kc * std::max(0.0, std::min(phi, allowed));
  }
  slip_grips();
  return pushed;
}

// Gripping nodes that were pulled beyond the limit slip: the anchor follows.
void Rod::slip_grips() {
  const double kg = settings_.contact_stiffness_mN_per_mm * settings_.stick_stiffness_ratio;
  for (std::size_t k = first_free_; k < x_.size(); ++k) {
    if (grip_limit_[k] <= 0.0) continue;
    const glm::dvec3 rel = x_[k] - grip_anchor_[k];
    const double len = glm::length(rel);
    if (kg * len > grip_limit_[k]) grip_anchor_[k] = x_[k] - rel * (grip_limit_[k] / (kg * len));
  }
}

}  // namespace cathbox::tool
