// One quasi-static step of the rod, as a sequence of named phases: the predictor moves the tool
// by the insertion change; the Newton solve (rod_newton.cpp) finds the node positions from a
// warm start; the nodes are held within the penetration limits of the wall and of other rods;
// then the frames and the twist (rod_twist.cpp), the contact forces (rod_wall_contact.cpp) and
// the force law for the box (rod_force_law.cpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "rod_newton.hpp"
#include "rod_node_contact.hpp"
#include "tool/banded_cholesky.hpp"
#include "tool/rod.hpp"

namespace cathbox::tool {

namespace {
constexpr int kProjectionRounds = 6;  // wall / rod-rod projections alternated after a solve
constexpr double kRegatherMargins = 0.1;  // own motion (in margins) that takes the planes afresh after a solve
}  // namespace

void Rod::step_once(double dt_s, const WallModel& wall, const RodObstacles* obstacles) {
  begin_step();
  edge_contacts_.clear();
  bool clamp_after_moves = false;
  if (first_free_ < x_.size()) {
    Newton s(wall, obstacles);
    start_solve(s, dt_s);
    solve_positions(s);
    clamp_after_moves = finish_solve(s);
  } else {
    hand_force_mN_ = 0.0;
    clamp_read_mN_ = 0.0;
    warm_ok_ = false;  // all in the catheter: its last solved motion is no guide when it comes out
  }
  update_frames();
  solve_twist(dt_s);
  finish_contacts();
  compute_force_law(dt_s, clamp_after_moves);
}

void Rod::begin_step() {
  const std::size_t n = x_.size();
  const std::size_t old_first = first_;
  for (std::size_t k = std::min(old_first, first_); k < n; ++k) x_start_[k] = x_[k];
  if (!free_) {
    const double advance =
        std::isfinite(material_advance_mm_) ? material_advance_mm_ : insertion_mm_ - stepped_insertion_mm_;
    material_advance_mm_ = std::numeric_limits<double>::quiet_NaN();
    advect(advance);
    update_window();  // (before the step's insertion is kept: the window holds still with it)
    stepped_insertion_mm_ = insertion_mm_;
  }
  for (std::size_t k = first_; k < old_first; ++k) x_start_[k] = x_[k];
  for (std::size_t k = first_; k + 1 < n; ++k) theta_start_[k] = theta_[k];
}

void Rod::start_solve(Newton& s, double dt_s) {
  const std::size_t n = x_.size();
  // Compressed and lying within one plane through its entry: seeded now.
  const bool seeded = compressed_ && seed_buckling();
  // Warm start from the last converged step's motion (never after a jammed step: a buckled
  // tool extrapolated keeps shaking; nor on a step seeded now: the extrapolation would carry the
  // last solve's taking the seed back out against the new seed). solved_move_ then keeps where
  // this step's solve starts from (the advected position), until the step's own motion is known.
  const bool warm = warm_ok_ && !jammed_ && !seeded && settings_.warm_start != 0.0;
  for (std::size_t k = first_free_; k < n; ++k) {
    const glm::dvec3 from = x_[k];
    if (warm && k >= warm_first_) x_[k] += solved_move_[k] * settings_.warm_start;
    solved_move_[k] = from;
  }
  warm_ok_ = false;
  update_weights(dt_s);
  if (free_) add_twist_holonomy_loads();
  refresh_contacts(s.wall, false);
  if (s.obstacles != nullptr) gather_obstacles(*s.obstacles);
  s.dofs = 3 * (n - first_);
  s.free0 = 3 * (first_free_ - first_);
  s.iterations = std::max(1, settings_.newton_iterations);
  // Active set: nodes touching now or at the end of the last step are held on their plane.
  for (std::size_t k = first_free_; k < n; ++k) {
    NodeContact& nc = node_contacts_[k];
    nc.active = nc.has_plane && (nc.normal_force > 0.0 || plane_gap(k) > 0.0);
    nc.active2 = nc.has_second && (nc.normal_force2 > 0.0 || second_gap(k) > 0.0);
    NodeContact::EdgeWall& ew = nc.edge;
    ew.active = ew.has_plane && k + 1 < n && (ew.normal_force > 0.0 || edge_wall_gap(k) > 0.0);
  }
  s.rounds = s.iterations;
  s.rejoin_from = n;
  std::fill(held_gap_.begin(), held_gap_.end(), std::numeric_limits<double>::quiet_NaN());
  // Joins are a solve's own: one on its last round (the round count at its limit) is never
  // amended into a system, and left set it would add its node's wall terms to a later solve's
  // join a second time (on top of the assembly's, or for a node long off the wall).
  std::fill(joined_.begin(), joined_.end(), std::uint8_t{0});
}

bool Rod::finish_solve(const Newton& s) {
  const std::size_t n = x_.size();
  settle_held_nodes();
  refresh_contacts(s.wall, true);
  limit_penetration();
  for (std::size_t k = first_free_; k < n; ++k) solved_move_[k] = x_[k] - solved_move_[k];
  warm_first_ = first_free_;
  project_contacts(s.obstacles);
  return linearise_clamp(s);
}

// A node held in the last iteration but past the limit (the step was cut to max_node_step_mm)
// goes where the Newton step it aimed at (the full one, half of a damped reversal) puts it along
// the wall normal: its force is the penalty's at the linearised equilibrium, not the clamp's cap.
void Rod::settle_held_nodes() {
  const std::size_t n = x_.size();
  for (std::size_t k = first_free_; k < n; ++k) {
    const NodeContact& nc = node_contacts_[k];
    const double phi = nc.has_plane ? plane_gap(k) : 0.0;
    const double allowed = settings_.max_penetration_ratio * radius_[k];
    if (nc.active && phi > allowed && held_gap_[k] < allowed) x_[k] -= nc.normal * (phi - std::max(0.0, held_gap_[k]));
  }
}

// Among other rods the wall and rod-rod projections alternate (a loop pressed on the sac by
// the next), each rod-rod round on planes gathered afresh: planes held from the iterations
// split a gap both sides have since moved across, and projecting on them pushed loops into
// the wall and into each other.
void Rod::project_contacts(const RodObstacles* obstacles) {
  for (int round = 0; round < (obstacles != nullptr ? kProjectionRounds : 1); ++round) {
    if (round > 0) limit_penetration();
    // Other rods are frozen while this one is solved: the planes of the solve are taken again
    // unless a node moved a tenth of the margin since they were gathered.
    if (obstacles != nullptr && (round > 0 || moved_since_gather(kRegatherMargins * obstacles->margin_mm()))) {
      gather_obstacles(*obstacles);
    }
    if (!finish_edge_contacts()) break;
  }
}

// The force on the clamp at the final state, to first order from the last assembly:
// g_p += K_pf (x - x_assembled). A rod among other rods (a coil, the catheter it leaves)
// often ends its step before its contacts settle; its clamp takes the last Newton step
// whole instead (the free part at the linearised equilibrium: g_p - K_pf K_ff^-1 g_f), so
// the residual of its stiff axial springs and of the final projections stays out of the hand.
bool Rod::linearise_clamp(const Newton& s) {
  const std::size_t n = x_.size();
  bool whole = s.obstacles != nullptr || settings_.linearised_clamp;
  for (std::size_t i = s.free0; whole && i < s.dofs; ++i) whole = std::isfinite(delta_[i]);
  for (std::size_t k = first_free_; k < n; ++k) {
    const std::size_t d = 3 * (k - first_);
    const glm::dvec3 moved = whole ? glm::dvec3(delta_[d], delta_[d + 1], delta_[d + 2]) : x_[k] - x_pred_[k];
    work_[d] = moved.x;
    work_[d + 1] = moved.y;
    work_[d + 2] = moved.z;
  }
  matrix_->multiply_add(work_.data(), grad_.data(), 0, s.free0, s.free0, s.dofs);
  // A solve that converged on a step it took in part (the line search cut it) or beyond (extended)
  // stopped off the linearised equilibrium its convergence test read: the rest of the step, through
  // the stiff axial springs, reads as force on the clamp (the ADAPT M1 run with its speeds x0.995:
  // -1,349 mN for one tick at 60.053 s, a converged 1.85 um step taken half; scripts/robustness).
  // The hand gets the equilibrium's force: the clamp rows of K_pf (step - moves), along the entry.
  whole_step_extra_mN_.reset();
  if (whole || !warm_ok_ || s.scale == 1.0) return !whole;
  for (std::size_t i = s.free0; i < s.dofs; ++i) {
    if (!std::isfinite(delta_[i])) return true;
    work_[i] = delta_[i] - work_[i];
  }
  if (clamp_rows_.size() < s.free0) clamp_rows_.resize(s.free0);
  std::fill(clamp_rows_.begin(), clamp_rows_.begin() + static_cast<std::ptrdiff_t>(s.free0), 0.0);
  matrix_->multiply_add(work_.data(), clamp_rows_.data(), 0, s.free0, s.free0, s.dofs);
  double extra = 0.0;
  for (std::size_t d = 0; d + 2 < s.free0; d += 3) {
    extra += glm::dot(glm::dvec3(clamp_rows_[d], clamp_rows_[d + 1], clamp_rows_[d + 2]), dir_);
  }
  whole_step_extra_mN_ = extra;
  return true;
}

}  // namespace cathbox::tool
