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
    const double kc = edge_stiffness(ec, kc_rod);
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

// The Newton step of an iteration, solved again with the penalty of the open planes it would
// cross. An open plane (the edge's point short of it) is out of the assembly, so the step went
// through it and the line search cut the whole step to 1/8-1/64 (a coil pushed into its sac:
// BM_StepCoilDeploy's capped steps). Each plane the step crosses takes its quadratic penalty,
// on both sides, into the step's model (into the factored matrix and the right-hand side, not
// into the gradient and the energy the line search reads) and the step is solved again; a
// plane so taken that the new step leaves open (it would pull) is taken out again, up to
// RodSettings::contact_predictions solves. The step then stops at the planes rather than short
// of them all. The model is this iteration's only: the next assembly has the penetrated planes.
void Rod::predict_edge_contacts(Newton& s) {
  // Not on a released coil: it settles in one iteration a step, and the solves again cost the
  // packing bench's step ~10 % of its median.
  if (settings_.contact_predictions <= 0 || free_ || edge_contacts_.empty()) return;
  predicted_.assign(edge_contacts_.size(), 0);
  bool any = false;
  for (int pass = 0; pass < settings_.contact_predictions; ++pass) {
    const std::size_t from = take_crossed_planes();
    if (from == x_.size()) break;
    if (!any) std::copy(delta_.begin(), delta_.begin() + static_cast<std::ptrdiff_t>(s.dofs), plain_delta_.begin());
    any = true;
    matrix_->refactor_from(from - first_);
    solve_with_taken_planes(s, from);
  }
  if (!any) return;
  s.refactor = true;  // the factor holds the planes: never reused as a chord
  // The energy must fall along it (the line search's slope); else the plain step.
  double slope = 0.0;
  for (std::size_t i = s.free0; i < s.dofs; ++i) slope += grad_[i] * delta_[i];
  const double largest = largest_update();
  if (!(slope < 0.0) || !std::isfinite(largest)) {
    std::copy(plain_delta_.begin(), plain_delta_.begin() + static_cast<std::ptrdiff_t>(s.dofs), delta_.begin());
    return;
  }
  s.largest = largest;
}

// One pass of predict_edge_contacts: the open planes the step in delta_ crosses are taken into
// the assembled matrix, those taken that it leaves open are taken out. Returns the first node
// whose blocks changed (the node count: none).
std::size_t Rod::take_crossed_planes() {
  const double kc_rod = settings_.contact_stiffness_mN_per_mm;
  const rod_detail::BlockAdder add{*matrix_, first_, true};
  const auto moved = [&](std::size_t k) {
    const std::size_t d = 3 * (k - first_);
    return k >= first_free_ ? glm::dvec3(delta_[d], delta_[d + 1], delta_[d + 2]) : glm::dvec3(0.0);
  };
  std::size_t from = x_.size();
  for (std::size_t i = 0; i < edge_contacts_.size(); ++i) {
    const EdgeContact& ec = edge_contacts_[i];
    const double phi = edge_gap(ec);
    if (phi > 0.0) continue;  // in the assembly
    const std::size_t a = ec.edge;
    const double wa = 1.0 - ec.s;
    const double wb = ec.s;
    const double after = phi - glm::dot(ec.normal, moved(a) * wa + moved(a + 1) * wb);
    double sign = 0.0;
    if (predicted_[i] == 0 && after > 0.0) sign = 1.0, predicted_[i] = 1;
    else if (predicted_[i] == 1 && after < 0.0) sign = -1.0, predicted_[i] = 0;
    if (sign == 0.0) continue;
    const glm::dmat3 nn = (sign * edge_stiffness(ec, kc_rod)) * glm::outerProduct(ec.normal, ec.normal);
    if (a >= first_free_) add(a, a, nn * (wa * wa));
    if (a + 1 >= first_free_) add(a + 1, a + 1, nn * (wb * wb));
    if (a >= first_free_) add(a + 1, a, nn * (wa * wb));
    from = std::min(from, std::max(a, first_free_));
  }
  return from;
}

// The Newton step on the factor holding the taken planes: the right-hand side is the gradient's
// with each taken plane's pull towards it (minus the gradient of kc phi^2 / 2, phi < 0). The
// planes taken or let go in this pass are at node `from` and later, where the factor was
// refactored: before it the right-hand side and the factor are the last solve's (the plain
// step's or the last pass's, the same planes adding the same pulls in the same order), so its
// forward pass there is kept.
void Rod::solve_with_taken_planes(const Newton& s, std::size_t from) {
  const double kc_rod = settings_.contact_stiffness_mN_per_mm;
  for (std::size_t i = 0; i < s.dofs; ++i) delta_[i] = i >= s.free0 ? -grad_[i] : 0.0;
  for (std::size_t i = 0; i < edge_contacts_.size(); ++i) {
    if (!predicted_[i]) continue;
    const EdgeContact& ec = edge_contacts_[i];
    const glm::dvec3 pull = ec.normal * (edge_stiffness(ec, kc_rod) * edge_gap(ec));
    for (std::size_t j = 0; j < 2; ++j) {
      const std::size_t k = ec.edge + j;
      if (k < first_free_) continue;
      const std::size_t d = 3 * (k - first_);
      const double w = j == 0 ? 1.0 - ec.s : ec.s;
      delta_[d] += pull.x * w;
      delta_[d + 1] += pull.y * w;
      delta_[d + 2] += pull.z * w;
    }
  }
  matrix_->solve_again(delta_.data(), from - first_);
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
    const double kc = edge_stiffness(ec, kc_rod);
    ec.force_mN = kc * std::max(0.0, std::min(phi, allowed));
  }
  slip_grips();
  return pushed;
}

// Gripping nodes that were pulled beyond the limit slip: the anchor follows.
void Rod::slip_grips() {
  const double kg = settings_.stick_stiffness_mN_per_mm();
  for (std::size_t k = first_free_; k < x_.size(); ++k) {
    if (grip_limit_[k] <= 0.0) continue;
    const glm::dvec3 rel = x_[k] - grip_anchor_[k];
    const double len = glm::length(rel);
    if (kg * len > grip_limit_[k]) grip_anchor_[k] = x_[k] - rel * (grip_limit_[k] / (kg * len));
  }
}

}  // namespace cathbox::tool
