// The Newton solve of a step: Gauss-Newton iterations on the node positions, each a sequence of
// named phases. The system is assembled (or, when nodes joined the wall's active set, amended)
// and factored; the Newton step is solved; nodes it would carry into the wall join and it is
// solved again; a two-cycle is damped; a backtracking line search on the step energy takes it;
// the active set follows the new positions; the wall is re-probed and other rods' planes taken
// again where nodes moved. Stops when the largest full Newton update is below RodSettings::convergence_mm.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "rod_newton.hpp"
#include "rod_node_contact.hpp"
#include "tool/banded_cholesky.hpp"
#include "tool/rod.hpp"
#include "tool/wall_penalty.hpp"

namespace cathbox::tool {

namespace {

// The axial springs' second-order stretch of a Newton step d. The Hessian holds each edge's
// spring to second order at the assembly, so a node carried sideways by m lengthens its edges by
// ~m^2 / 2l beyond the model (a coil's EA / l of 10^7 mN/mm reads 20 um sideways over a 0.5 mm
// edge as 0.8 mN.mm): the full step's energy rises and the line search cuts it. The correction
// c = -H^-1 r (a second-order correction, Nocedal & Wright, Numerical Optimization, 2006, §18.3),
// r each edge's length at the full step beyond the model's times its EA / l, along the edge as
// assembled, on the factor that gave the step (into `c`, the rod's scratch, unused until the
// solve ends), takes that stretch back along the edges; the step then follows x + t d + t^2 c,
// the stretch of t d being t^2 that of d.
struct StretchStep {
  std::vector<glm::dvec3>& x;
  const std::vector<glm::dvec3>& x_pred;  // the free nodes where the system was assembled
  const std::vector<double>& d;
  std::vector<double>& c;
  std::size_t first, first_free;

  [[nodiscard]] glm::dvec3 dof3(const std::vector<double>& v, std::size_t k) const {
    const std::size_t i = 3 * (k - first);
    return k >= first_free ? glm::dvec3(v[i], v[i + 1], v[i + 2]) : glm::dvec3(0.0);
  }
  // Free nodes at x_pred + t d + t^2 c.
  void place(double t) const {
    for (std::size_t k = first_free; k < x.size(); ++k) x[k] = x_pred[k] + dof3(d, k) * t + dof3(c, k) * (t * t);
  }
  // c for the full step; false when it is not finite.
  bool correct(const std::vector<double>& axial_k, const BandedCholesky& h,
               std::size_t free0, std::size_t dofs) const {
    const std::size_t n = x.size();
    std::fill(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(dofs), 0.0);
    const auto at = [&](std::size_t k) { return k >= first_free ? x_pred[k] : x[k]; };
    const auto pull = [&](std::size_t k, const glm::dvec3& f) {  // the right-hand side, -r
      if (k < first_free) return;
      const std::size_t i = 3 * (k - first);
      c[i] -= f.x;
      c[i + 1] -= f.y;
      c[i + 2] -= f.z;
    };
    for (std::size_t k = std::max(first, first_free > 0 ? first_free - 1 : 0); k + 1 < n; ++k) {
      const glm::dvec3 e = at(k + 1) - at(k);
      const glm::dvec3 step = dof3(d, k + 1) - dof3(d, k);
      const double len = std::max(glm::length(e), 1e-12);
      const glm::dvec3 u = e * (1.0 / len);
      // The edge's length at the full step beyond the model's (len + u.step), as a force along
      // the edge as assembled (the constraint's gradient there; the force's turn with the edge
      // pulled a soft coil's nodes sideways by millimetres).
      const double over = glm::length(e + step) - len - glm::dot(u, step);
      const glm::dvec3 r = u * (axial_k[k] * over);
      pull(k + 1, r);
      pull(k, -r);
    }
    h.solve(c.data());
    for (std::size_t i = free0; i < dofs; ++i) {
      if (!std::isfinite(c[i])) return false;
    }
    return true;
  }
};

// A coil not yet released: the tools with the arc predictor that have a clamp. Its line search
// follows the curve below, and a join round (nodes the step would carry into the wall, solved
// again held, no iterate) is a round of its own: the deploy's capped steps spent 2.1-2.8 of their
// 8 rounds on joins. Elsewhere a join is one of the cap (a round of its own on every rod moved
// the steered wire's and the bundled sac's tests), and a released coil, which settles in one
// iteration a step, is spared the correction's solve (the packing bench's median).
bool attached_coil(const RodSettings& settings, bool released) { return settings.arc_predictor && !released; }

}  // namespace

void Rod::solve_positions(Newton& s) {
  for (int it = 0; it < s.rounds; ++it) {
    build_system(s);
    if (!newton_direction(s)) break;  // keep the previous positions; never propagate NaN
    if (join_wall(s, it)) continue;
    predict_edge_contacts(s);
    damp_reversal(s);
    line_search(s);
    hold_gaps(s);
    update_active_set(s);
    follow_moves(s);
    last_iterations_ = it + 1;
    const bool pulled = s.released_pull_mN > settings_.release_pull_mN;  // a node let go under a pull
    if (s.largest < settings_.convergence_mm && !s.entered && !pulled) {
      warm_ok_ = true;
      break;
    }
    // A node left in the wall at the end would be clamped at the penetration limit, which
    // reads as the contact cap, and one let go under a pull would leave that pull in the clamp's
    // force: up to two more iterations settle either.
    const int joins = attached_coil(settings_, free_) ? s.activations : 0;
    if ((s.entered || s.deep || pulled) && it + 1 == s.rounds && s.rounds < s.iterations + joins + 2) ++s.rounds;
  }
}

void Rod::build_system(Newton& s) {
  const std::size_t n = x_.size();
  if (s.rejoin) {
    add_joined_wall_terms(s);
  } else {
    assemble(s.refactor);
    for (std::size_t k = first_free_; k < n; ++k) x_pred_[k] = x_[k];  // where grad_ holds
  }
  // After a join only the joined nodes' diagonal blocks changed: factor again from the
  // first of them (the rows before it are the last factorisation's, bit for bit).
  if (s.refactor && s.rejoin_from < n) {
    matrix_->refactor_from(s.rejoin_from - first_);
  } else if (s.refactor) {
    matrix_->factor(first_free_ - first_);
  }
  s.rejoin_from = n;
  s.fresh = s.refactor;
  s.refactor = !settings_.reuse_hessian;
}

// Amends the assembly (the factorisation leaves it intact) with the wall terms of the nodes
// that joined.
void Rod::add_joined_wall_terms(Newton& s) {
  const std::size_t n = x_.size();
  const rod_detail::BlockAdder add{*matrix_, first_, true};
  const WallPenalty wall(settings_);
  s.rejoin_from = n;
  for (std::size_t k = first_free_; k < n; ++k) {
    if (!joined_[k]) continue;
    s.rejoin_from = std::min(s.rejoin_from, k);
    const NodeContact& nc = node_contacts_[k];
    const std::size_t d = 3 * (k - first_);
    for (int j = 0; j < 2; ++j) {
      if (!(joined_[k] & (1 << j))) continue;
      const glm::dvec3 normal = j == 0 ? gap_normal(k) : nc.normal2;
      const double phi = j == 0 ? plane_gap(k) : second_gap(k);
      const double kw = wall.stiffness_mN_per_mm(phi);
      add(k, k, kw * glm::outerProduct(normal, normal));
      // Within the layer n K w, rounded as the rigid wall always had it; past it the stiffer law.
      const glm::dvec3 g = phi <= wall.layer_mm ? normal * kw * phi : normal * wall.gradient_mN(phi);
      grad_[d] += g.x;
      grad_[d + 1] += g.y;
      grad_[d + 2] += g.z;
      energy_ += wall.energy(phi);
    }
    if (joined_[k] & 4) add_edge_wall_term(k, true);
    joined_[k] = 0;
  }
  s.rejoin = false;
}

bool Rod::newton_direction(Newton& s) {
  for (std::size_t i = 0; i < s.dofs; ++i) delta_[i] = i >= s.free0 ? -grad_[i] : 0.0;
  matrix_->solve_keeping(delta_.data());  // predict_edge_contacts solves it again from a row
  s.largest = largest_update();
  return std::isfinite(s.largest);
}

double Rod::largest_update() const {
  double largest = 0.0;
  for (std::size_t k = first_free_; k < x_.size(); ++k) {
    const std::size_t d = 3 * (k - first_);
    const double m = std::sqrt(delta_[d] * delta_[d] + delta_[d + 1] * delta_[d + 1] + delta_[d + 2] * delta_[d + 2]);
    largest = std::max(largest, m);
  }
  return largest;
}

// Nodes off the wall that the step would carry into it join the active set (at most three
// times a step); the caller solves again.
bool Rod::join_wall(Newton& s, int it) {
  const std::size_t n = x_.size();
  bool joined = false;
  for (std::size_t k = first_free_; k < n && s.activations < 3; ++k) {
    NodeContact& nc = node_contacts_[k];
    if (!nc.has_plane) continue;
    const std::size_t d = 3 * (k - first_);
    const glm::dvec3 step(delta_[d], delta_[d + 1], delta_[d + 2]);
    if (!nc.active && plane_gap(k) + glm::dot(nc.normal, step) > 0.0) {
      nc.active = true;
      joined = true;
      joined_[k] |= 1;
    }
    if (nc.has_second && !nc.active2 && second_gap(k) + glm::dot(nc.normal2, step) > 0.0) {
      nc.active2 = true;
      joined = true;
      joined_[k] |= 2;
    }
  }
  if (s.activations < 3 && join_edge_walls()) joined = true;
  if (!joined) return false;
  ++s.activations;
  // A round of its own on an attached coil; elsewhere one of the cap, but the last (to hold them).
  if (attached_coil(settings_, free_) || (it + 1 == s.rounds && s.rounds < s.iterations + 2)) ++s.rounds;
  s.refactor = true;
  s.rejoin = true;
  return true;
}

// The step is cut to max_node_step_mm. An update too small for the line search that nearly
// undoes the last one is a two-cycle (friction at its stick-slip edge, a crease plane let go and
// taken back): half of it lands between the two states, where the solution is.
void Rod::damp_reversal(Newton& s) {
  s.scale = s.largest > settings_.max_node_step_mm ? settings_.max_node_step_mm / s.largest : 1.0;
  s.aim = 1.0;
  if (s.stepped && settings_.damp_reversals && s.largest * s.scale < settings_.trust_step_mm) {
    double dot = 0.0, now = 0.0, before = 0.0;
    for (std::size_t i = s.free0; i < s.dofs; ++i) {
      dot += delta_[i] * last_step_[i];
      now += delta_[i] * delta_[i];
      before += last_step_[i] * last_step_[i];
    }
    if (dot < -0.9 * std::sqrt(now * before)) s.scale *= 0.5, s.aim = 0.5;
  }
}

// Backtracking line search on the step energy (contacts and friction are non-smooth), on every
// update however small: a node at the edge of its friction stick zone (its stick spring
// inside, a constant μN outside, whose Hessian has no stiffness along the slip) is sent across the
// edge and back by full Gauss-Newton steps of a few µm, step after step, and never meets the
// convergence test (the angioplasty run's guidewire: 20 % of its ticks).
//
// On an attached coil every try is on the curve x + t d + t^2 c, c the
// correction of the axial springs' second-order stretch (StretchStep, above), and no step is
// extended.
void Rod::line_search(Newton& s) {
  const double e0 = energy_;
  double slope = 0.0;
  for (std::size_t i = s.free0; i < s.dofs; ++i) slope += grad_[i] * delta_[i];
  double e1 = e0;
  const StretchStep step{x_, x_pred_, delta_, work_, first_, first_free_};
  const bool curved = attached_coil(settings_, free_) && step.correct(axial_k_, *matrix_, s.free0, s.dofs);
  for (int tries = 0;; ++tries) {
    if (curved) {
      step.place(s.scale);
    } else {
      place(s.scale);
    }
    if (tries >= 6 || slope >= 0.0) break;
    ++retired_work_.line_tries;
    e1 = energy();
    if (e1 <= e0 + 1e-4 * s.scale * slope) {
      if (tries == 0 && s.scale == 1.0 && !curved) extend(s, slope, e0, e1);
      break;
    }
    s.scale *= 0.5;
    if (!s.fresh) s.refactor = true;  // a stale Hessian gave a poor step
  }
  for (std::size_t i = s.free0; i < s.dofs; ++i) last_step_[i] = delta_[i] * s.scale;
  s.stepped = true;
}

void Rod::place(double scale) {
  for (std::size_t k = first_free_; k < x_.size(); ++k) {
    const std::size_t d = 3 * (k - first_);
    x_[k] = x_pred_[k] + glm::dvec3(delta_[d], delta_[d + 1], delta_[d + 2]) * scale;
  }
}

// A full step whose energy fell by more than the Hessian's quadratic model said (e(1) below
// e0 + slope / 2) went along a mode the Hessian holds stiffer than the energy: the parabola
// through e0, the slope and e(1) has its minimum at t = -slope / (2 (e1 - e0 - slope)) > 1.
// The step is taken there (at most extend_max and the largest update's cap; not below 2) if the
// energy is lower than at 1.
void Rod::extend(Newton& s, double slope, double e0, double e1) {
  const double curvature = 2.0 * (e1 - e0 - slope);
  if (!(settings_.extend_max > 1.0) || !(curvature > 0.0)) return;
  double t = std::min(-slope / curvature, settings_.extend_max);
  if (s.largest > 0.0) t = std::min(t, settings_.max_node_step_mm / s.largest);
  if (t < 2.0) return;  // (from 1.25 or 1.05 the dead ends' shares were 2.6-2.7 and 2.0-2.1 %)
  place(t);
  if (energy() < e1) {
    s.scale = t;
    s.aim = t;
    return;
  }
  place(1.0);
}

// Each held node's wall gap at the end of the Newton step it aims at (finish_solve settles a
// node left past the limit there).
void Rod::hold_gaps(const Newton& s) {
  const std::size_t n = x_.size();
  for (std::size_t k = first_free_; k < n; ++k) {
    const NodeContact& nc = node_contacts_[k];
    const std::size_t d = 3 * (k - first_);
    const glm::dvec3 rest(delta_[d], delta_[d + 1], delta_[d + 2]);
    held_gap_[k] = nc.active ? plane_gap(k) + (s.aim - s.scale) * glm::dot(nc.normal, rest)
                             : std::numeric_limits<double>::quiet_NaN();
  }
}

// Nodes the wall would have to pull leave the active set; nodes the step carried into the wall
// (after the activation rounds ran out) join it for the next iteration. `entered`: one of them
// is deeper than a hundredth of the penetration limit (the convergence test does not stop on
// it: the end of the step might clamp it); `deep`: a held node is past the limit.
void Rod::update_active_set(Newton& s) {
  const std::size_t n = x_.size();
  s.entered = false;
  s.deep = false;
  s.released_pull_mN = 0.0;
  const WallPenalty wall(settings_);
  const auto update = [&](bool& active, double phi, double allowed) {
    if (active && phi < -1e-9) {
      s.released_pull_mN = std::max(s.released_pull_mN, -wall.gradient_mN(phi));
      active = false;
      s.refactor = true;
    } else if (!active && phi > 0.0) {
      active = true;
      s.refactor = true;
      s.entered = s.entered || phi > 0.01 * allowed;
    } else {
      s.deep = s.deep || (active && phi > allowed);
    }
  };
  for (std::size_t k = first_free_; k < n; ++k) {
    NodeContact& nc = node_contacts_[k];
    if (!nc.has_plane) continue;
    const double allowed = settings_.max_penetration_ratio * radius_[k];
    update(nc.active, plane_gap(k), allowed);
    if (nc.has_second) update(nc.active2, second_gap(k), allowed);
  }
  update_edge_wall_set(s);
}

void Rod::follow_moves(Newton& s) {
  const std::size_t n = x_.size();
  if (refresh_contacts(s.wall, true, true)) s.refactor = true;
  if (s.obstacles == nullptr) return;
  // A node the re-probe finds in the wall joins the active set now: among other rods (a coil in
  // its sac) the joins of the iterations above are soon spent, and a node left out was carried
  // deep into the wall and thrown back by the projection after the solve.
  for (std::size_t k = first_free_; k < n; ++k) {
    NodeContact& nc = node_contacts_[k];
    if (!nc.has_plane) continue;
    if (!nc.active && plane_gap(k) > 0.0) nc.active = true, s.refactor = true;
    if (nc.has_second && !nc.active2 && second_gap(k) > 0.0) nc.active2 = true, s.refactor = true;
  }
  // Planes of other rods are taken again once a node has moved half the margin.
  if (moved_since_gather(0.5 * s.obstacles->margin_mm())) {
    gather_obstacles(*s.obstacles);
    s.refactor = true;
  }
}

}  // namespace cathbox::tool
