// The force law the box renders between steps: the force and torque at the hand, their
// stiffness (the Schur complement of the factored free block on a unit insertion) and the
// physical damping, with the solver's numerical damping taken back out of what the hand feels.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "tool/banded_cholesky.hpp"
#include "tool/rod.hpp"

namespace cathbox::tool {

void Rod::compute_force_law(double dt_s, bool clamp_after_moves) {
  const std::size_t n = x_.size();
  law_.insertion0_mm = insertion_mm_;
  law_.rotation0_rad = rotation_rad_;
  // The hand feels the physical drag only: the solver's floor above it (numerical damping) is
  // taken back out of the force below, and the law renders the physical damping.
  double drag_total = 0.0;       // what the solver used
  double physical_total = 0.0;
  double rot_physical_total = 0.0;
  glm::dvec3 numerical_drag(0.0);
  for (std::size_t k = first_free_; k < n; ++k) {
    const double physical = drag_per_mm_[k] * voronoi_[k];
    drag_total += solver_drag(k);
    physical_total += physical;
    rot_physical_total += physical * radius_[k] * radius_[k];
    numerical_drag += (solver_drag(k) - physical) / dt_s * (x_[k] - x_start_[k]);
  }
  law_.damping_mN_s_per_mm = physical_total;
  law_.torsion_damping_mNmm_s_per_rad = rot_physical_total;
  law_.torque0_mNmm = hand_torque_mNmm_;
  clamp_force_ = glm::dvec3(0.0);
  free_part_load_mN_ = 0.0;
  if (first_free_ >= n || free_) {
    hand_force_mN_ = 0.0;
    clamp_read_mN_ = 0.0;
    law_.force0_mN = 0.0;
    law_.stiffness_mN_per_mm = 0.0;
    return;
  }
  // Axial force on the clamp: the energy gradient on the outside nodes along the entry.
  for (std::size_t k = first_; k < first_free_; ++k) {
    const std::size_t d = 3 * (k - first_);
    clamp_force_ += glm::dvec3(grad_[d], grad_[d + 1], grad_[d + 2]);
  }
  // The numerical damping on the free nodes reaches the clamp through the rod: out of the hand.
  const double force = glm::dot(clamp_force_, dir_) - glm::dot(numerical_drag, dir_);
  free_part_load_mN_ = sum_free_part_loads(dt_s);
  // The clamp holds the free part against the sum of the external forces on it, so no more than
  // their magnitudes sum to. A clamp linearised on to the moves after the solve (penetration
  // limits, projections: they report no force; linearise_clamp) can read more, balanced by
  // nothing: a wire jammed 15 mm out of its microcatheter read 12.8 N against its free part's
  // 2.2 N. The hand gets the bound. A clamp that takes the last Newton step whole has no such
  // moves in it: it is the linearised equilibrium, kept as it is.
  clamp_read_mN_ = clamp_after_moves ? std::clamp(force, -free_part_load_mN_, free_part_load_mN_) : force;
  // A converged step taken in part: the force at its linearised equilibrium (linearise_clamp).
  hand_force_mN_ = whole_step_extra_mN_ ? force + *whole_step_extra_mN_ : clamp_read_mN_;
  law_.force0_mN = hand_force_mN_;
  // Stiffness: Schur complement of the (factored) free block on a unit insertion.
  const std::size_t dofs = 3 * (n - first_);
  const std::size_t free0 = 3 * (first_free_ - first_);
  std::fill(work_.begin(), work_.begin() + static_cast<std::ptrdiff_t>(dofs), 0.0);
  for (std::size_t k = first_; k < first_free_; ++k) {
    const std::size_t d = 3 * (k - first_);
    work_[d] = dir_.x;
    work_[d + 1] = dir_.y;
    work_[d + 2] = dir_.z;
  }
  std::fill(delta_.begin(), delta_.begin() + static_cast<std::ptrdiff_t>(dofs), 0.0);
  matrix_->multiply_add(work_.data(), delta_.data(), 0, dofs, 0, free0);  // K[:, p] d
  double kpp = 0.0;
  for (std::size_t i = 0; i < free0; ++i) kpp += work_[i] * delta_[i];
  double coupling = 0.0;
  for (std::size_t i = free0; i < dofs; ++i) work_[i] = delta_[i];
  matrix_->solve(work_.data());
  for (std::size_t i = free0; i < dofs; ++i) coupling += delta_[i] * work_[i];
  const double k_with_drag = kpp - coupling;
  law_.stiffness_mN_per_mm = std::max(0.0, k_with_drag - drag_total / dt_s);
}

// The external forces on the free nodes, each by its magnitude (Rod::free_part_load_mN): the
// drag of the step's motion and the loads (node_terms), a grip's pull on its anchor (its slip
// limit at most: add_grip_terms), the wall contacts' normal force and friction, and the rod-rod
// and self contacts on an edge with a free end.
double Rod::sum_free_part_loads(double dt_s) const {
  const std::size_t n = x_.size();
  const double kg = settings_.stick_stiffness_mN_per_mm();
  double sum = 0.0;
  for (std::size_t k = first_free_; k < n; ++k) {
    const glm::dvec3 twist = k < twist_load_.size() ? twist_load_[k] : glm::dvec3(0.0);
    sum += solver_drag(k) / dt_s * glm::length(x_[k] - x_start_[k]) + glm::length(load_[k] + coupling_[k] + twist);
    if (grip_limit_[k] > 0.0) sum += std::min(grip_limit_[k], kg * glm::length(x_[k] - grip_anchor_[k]));
  }
  for (const RodContact& c : contacts_) {
    if (c.node >= first_free_) sum += std::abs(c.normal_force_mN) + glm::length(c.friction_mN);
  }
  for (const EdgeContact& c : edge_contacts_) {
    if (c.edge + 1 >= first_free_) sum += std::abs(c.force_mN);
  }
  return sum;
}

}  // namespace cathbox::tool
