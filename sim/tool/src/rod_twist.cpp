// Frames and twist: the reference frames carried along by parallel transport (time-parallel,
// Bergou et al. 2010) and the reference twist at each vertex; then the quasi-static twist
// angles by a tridiagonal Newton solve (torsion, the pre-curve's coupling, drag and torsional
// wall friction), the material frames, and the torque and torsional stiffness at the hand.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "base/portable_math.hpp"
#include "rod_geometry.hpp"
#include "rod_newton.hpp"
#include "rod_node_contact.hpp"
#include "tool/banded_cholesky.hpp"
#include "tool/rod.hpp"
#include "tool/wall_penalty.hpp"

namespace cathbox::tool {

using rod_detail::perpendicular_unit;
using rod_detail::transport;

void Rod::update_frames() {
  const std::size_t n = x_.size();
  for (std::size_t k = first_edge(); k + 1 < n; ++k) {
    const glm::dvec3 e = x_[k + 1] - x_[k];
    const double len = glm::length(e);
    if (!(len > 1e-12)) continue;
    const glm::dvec3 t = e / len;
    glm::dvec3 d1 = transport(d1_[k], t_[k], t);
    d1 = d1 - t * glm::dot(d1, t);
    const double dl = glm::length(d1);
    d1_[k] = dl > 1e-9 ? d1 / dl : perpendicular_unit(t);
    t_[k] = t;
  }
  for (std::size_t i = first_ + 1; i + 1 < n; ++i) {
    const glm::dvec3 v = transport(d1_[i - 1], t_[i - 1], t_[i]);
    ref_twist_[i] = base::portable::atan2(glm::dot(glm::cross(v, d1_[i]), t_[i]), glm::dot(v, d1_[i]));
  }
}

[[gnu::always_inline]] inline void Rod::set_material_frame(std::size_t e) {
  const glm::dvec3 d2 = glm::cross(t_[e], d1_[e]);
  double s = 0.0, c = 0.0;
  base::portable::sincos(theta_[e], s, c);
  m1_[e] = d1_[e] * c + d2 * s;
  m2_[e] = d2 * c - d1_[e] * s;
}

// Thomas' forward and back substitution of tw_rhs_ (m unknowns) with the inverse pivots tw_inv_
// of the twist system (off[j] couples j-1 and j): the twist update, and the hand's Schur complement.
void Rod::twist_substitute(std::size_t m) {
  for (std::size_t j = 1; j < m; ++j) tw_rhs_[j] -= tw_off_[j] * tw_inv_[j - 1] * tw_rhs_[j - 1];
  tw_rhs_[m - 1] *= tw_inv_[m - 1];
  for (std::size_t j = m - 1; j-- > 0;) tw_rhs_[j] = (tw_rhs_[j] - tw_off_[j + 1] * tw_rhs_[j + 1]) * tw_inv_[j];
}

void Rod::solve_twist(double dt_s) {
  const std::size_t n = x_.size();
  const std::size_t ef = first_edge();  // first free edge; edge ef - 1 is clamped (unless free)
  const std::size_t m = n - 1 - ef;        // free edges
  const bool solve = m > 0 && first_free_ < n;
  if (solve) {
    const int iterations = std::max(1, settings_.twist_iterations);
    for (int it = 0; it < iterations; ++it) {
      // The system is linear but for the pre-curve coupling and the friction's stick / slip
      // switch: without the one, and with every contact in the same regime after the update as
      // before it, the update solved it exactly and a further iteration would not move.
      bool linear = assemble_twist(dt_s, ef, m);
      add_twist_friction(ef);
      linear = update_twist(ef, m, linear);
      if (!linear || it + 1 == iterations) continue;
      if (twist_regimes_same()) break;
    }
  }
  if (solve && !free_) {
    hand_twist(dt_s, ef, m);
  } else {
    law_.torsion_stiffness_mNmm_per_rad = 0.0;
    hand_torque_mNmm_ = 0.0;
  }
  for (std::size_t e = first_; e + 1 < n; ++e) set_material_frame(e);
}

// The twist system of the m free edges from ef on: drag, torsion at every vertex between edges
// i-1 and i, and the pre-curve's coupling. False when that coupling makes it nonlinear.
bool Rod::assemble_twist(double dt_s, std::size_t ef, std::size_t m) {
  const std::size_t n = x_.size();
  bool linear = true;
  for (std::size_t j = 0; j < m; ++j) {
    const std::size_t e = ef + j;
    const double r = radius_[e + 1];
    const double c = solver_drag(e + 1) * r * r / dt_s + 1e-9;
    tw_diag_[j] = c;
    tw_off_[j] = 0.0;
    tw_rhs_[j] = c * (theta_[e] - theta_start_[e]);
  }
  // Twist at every vertex i between edges i-1 and i.
  TwistSweep sweep;
  for (std::size_t i = free_ ? 1 : ef; i + 1 < n; ++i) {
    const double c = gj_[i] / (i == ef && !free_ ? 0.5 * rest_[i] : voronoi_[i]);
    const double tau = theta_[i] - theta_[i - 1] + ref_twist_[i];
    const std::size_t j = i - ef;
    tw_diag_[j] += c;
    tw_rhs_[j] += c * tau;
    if (i - 1 >= ef) {
      tw_diag_[j - 1] += c;
      tw_rhs_[j - 1] -= c * tau;
      tw_off_[j] -= c;
    }
    if (kbar1_[i] != 0.0 || kbar2_[i] != 0.0) {
      linear = false;
      add_twist_curvature(i, ef, sweep);
    }
  }
  return linear;
}

// Pre-curved sections: the bending at vertex i depends on the edge angles through the rest turn
// towards the material frame. A released coil's twist minimises the bending energy its position
// solve does (Rod::bend_residual, E = w/2 |r|^2, with dm1/dtheta = m2, dm2/dtheta = -m1): a twist
// solve on another bending energy (add_twist_curvature_kb) and a position solve on this one,
// taken in turn, never came to rest (a coil left in a sphere turned at 8-18 um a tick for ever;
// docs/sim-tool/convergence.md). Attached tools keep the binormal form, not yet measured.
void Rod::add_twist_curvature(std::size_t i, std::size_t ef, TwistSweep& sweep) {
  if (!free_) {
    add_twist_curvature_kb(i, ef, sweep);
    return;
  }
  if (sweep.framed != i - 1) set_material_frame(i - 1);
  set_material_frame(i);
  sweep.framed = i;
  const glm::dvec3 ta = sweep.tangent_edge == i - 1 ? sweep.tangent : glm::normalize(x_[i] - x_[i - 1]);
  const glm::dvec3 tb = glm::normalize(x_[i + 1] - x_[i]);
  sweep.tangent_edge = i;
  sweep.tangent = tb;
  const glm::dvec3 r = bend_residual(i, ta, tb);
  const double w = bend_w_[i];
  for (std::size_t e = i - 1; e <= i; ++e) {
    if (e < ef) continue;
    const glm::dvec3 dr = (m2_[e] * kturn1_[i] - m1_[e] * kturn2_[i]) * -0.5;  // dr/dtheta_e
    const glm::dvec3 ddr = (m1_[e] * kturn1_[i] + m2_[e] * kturn2_[i]) * 0.5;  // d2r/dtheta_e^2
    tw_rhs_[e - ef] += w * glm::dot(dr, r);
    tw_diag_[e - ef] += w * (glm::dot(dr, dr) + std::max(0.0, glm::dot(ddr, r)));
  }
}

// A released coil's twist energy GJ/2l tau_i^2 on its centreline: the reference twist psi_i at
// vertex i turns with the nodes, d(psi_i)/dx_{i-1} = -kb / (2 l_a), d(psi_i)/dx_{i+1} = kb / (2 l_b)
// and minus their sum at x_i (kb the discrete curvature binormal; Bergou et al. 2008, Discrete
// Elastic Rods, sec. 7; the sign is this code's psi, checked by finite differences). The position
// solve takes it to second order from where it starts, with the twist angles of the last step:
// the moment GJ tau / l times d(psi)/dx as a load, and GJ/l d(psi)/dx d(psi)/dx^T (positive
// semi-definite) as its stiffness. Without the load a coil left in a sphere never came to rest;
// with the load alone (explicit, no stiffness) its solves went unconverged on 4.6 % of the
// coiling case's ticks (docs/sim-tool/convergence.md).
void Rod::add_twist_holonomy_loads() {
  const std::size_t n = x_.size();
  twist_load_.assign(n, glm::dvec3(0.0));
  twist_c_.assign(n, 0.0);
  twist_dpsi_.assign(3 * n, glm::dvec3(0.0));
  twist_x0_.assign(x_.begin(), x_.end());
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const glm::dvec3 a = x_[i] - x_[i - 1], b = x_[i + 1] - x_[i];
    const double la = glm::length(a), lb = glm::length(b);
    const glm::dvec3 kb = glm::cross(a, b) * (2.0 / std::max(la * lb + glm::dot(a, b), 1e-12));
    const double c = gj_[i] / voronoi_[i];
    const double moment = c * (theta_[i] - theta_[i - 1] + ref_twist_[i]);
    const glm::dvec3 da = kb * (-0.5 / std::max(la, 1e-12));  // d(psi_i)/dx_{i-1}
    const glm::dvec3 db = kb * (0.5 / std::max(lb, 1e-12));   // d(psi_i)/dx_{i+1}
    twist_load_[i - 1] -= da * moment;
    twist_load_[i + 1] -= db * moment;
    twist_load_[i] += (da + db) * moment;
    if (i - 1 < std::max(first_free_, first_)) continue;
    twist_c_[i] = c;
    twist_dpsi_[3 * i] = da;
    twist_dpsi_[3 * i + 1] = -(da + db);
    twist_dpsi_[3 * i + 2] = db;
  }
}

namespace {
// The linearised change of a vertex's reference twist, d(psi)/dx . (x - x0) over its three nodes.
[[gnu::always_inline]] inline double psi_change(const glm::dvec3* dpsi, const glm::dvec3* x, const glm::dvec3* x0) {
  double s = 0.0;
  for (std::size_t j = 0; j < 3; ++j) s += glm::dot(dpsi[j], x[j] - x0[j]);
  return s;
}
}  // namespace

// The twist's stiffness on the nodes, 1/2 GJ/l (d(psi_i)/dx . (x - x0))^2 per vertex: its
// gradient, energy and Hessian blocks (add_twist_holonomy_loads).
void Rod::add_twist_stiffness(bool hessian) {
  const std::size_t n = std::min(x_.size(), twist_c_.size());
  const rod_detail::BlockAdder add{*matrix_, first_, hessian};
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double c = twist_c_[i];
    if (c == 0.0) continue;
    const glm::dvec3* g = &twist_dpsi_[3 * i];
    const double s = psi_change(g, &x_[i - 1], &twist_x0_[i - 1]);
    energy_ += 0.5 * c * s * s;
    for (std::size_t j = 0; j < 3; ++j) {
      add_grad(i - 1 + j, g[j] * (c * s));
      for (std::size_t k = 0; k <= j; ++k) add(i - 1 + j, i - 1 + k, glm::outerProduct(g[j], g[k]) * c);
    }
  }
}

double Rod::twist_stiffness_energy() const {
  const std::size_t n = std::min(x_.size(), twist_c_.size());
  double e = 0.0;
  for (std::size_t i = 1; i + 1 < n; ++i) {
    if (twist_c_[i] == 0.0) continue;
    const double s = psi_change(&twist_dpsi_[3 * i], &x_[i - 1], &twist_x0_[i - 1]);
    e += 0.5 * twist_c_[i] * s * s;
  }
  return e;
}

// The discrete curvature binormal's material components against kbar: E = w/2 |k - kbar|^2
// with dk1/dtheta = k2, dk2/dtheta = -k1.
void Rod::add_twist_curvature_kb(std::size_t i, std::size_t ef, TwistSweep& sweep) {
  const glm::dvec3 a = x_[i] - x_[i - 1];
  const glm::dvec3 b = x_[i + 1] - x_[i];
  const double chi = std::max(glm::length(a) * glm::length(b) + glm::dot(a, b), 1e-12);
  const glm::dvec3 kb = glm::cross(a, b) * (2.0 / chi);
  const double w = 0.5 * (ei_[i] + ei_extra_[i]) / voronoi_[i];
  for (std::size_t e = i - 1; e <= i; ++e) {
    if (e < ef) continue;
    if (e != sweep.framed) set_material_frame(e);
    sweep.framed = e;
    const double k1 = glm::dot(kb, m2_[e]);
    const double k2 = -glm::dot(kb, m1_[e]);
    tw_rhs_[e - ef] += w * (kbar2_[i] * k1 - kbar1_[i] * k2);
    tw_diag_[e - ef] += w * std::max(0.0, kbar1_[i] * k1 + kbar2_[i] * k2);
  }
}

// Torsional wall friction at node k: stick spring with a slip limit. Returns 0 off the wall (or
// without friction), 1 stuck, 2 or 3 slipping either way, with the spring, its limit and the
// angle from the anchor.
[[gnu::always_inline]] inline std::uint8_t Rod::twist_regime(std::size_t k, double& ktr, double& limit, double& d) const {
  const std::size_t n = x_.size();
  const double kt = wall_stick_mN_per_mm(k);
  const NodeContact& nc = node_contacts_[k];
  const double mu = friction_at(k);
  if (!nc.has_plane || mu <= 0.0) return 0;
  const double phi = plane_gap(k);
  if (phi <= 0.0) return 0;
  const double r = radius_[k];
  ktr = kt * r * r;
  const WallPenalty wall(settings_);
  // mu K w r as the rigid wall always had it (the same rounding); past a layer, the stiffer law.
  limit = phi <= wall.layer_mm ? mu * wall.k_mN_per_mm * phi * r : mu * wall.force_mN(phi) * r;
  d = theta_[std::min(k, n - 2)] - nc.twist_anchor;
  if (ktr * std::abs(d) <= limit) return 1;  // stick
  return d > 0.0 ? 2 : 3;                    // slip either way
}

void Rod::add_twist_friction(std::size_t ef) {
  const std::size_t n = x_.size();
  for (std::size_t k = first_free_; k < n; ++k) {
    double ktr = 0.0, limit = 0.0, d = 0.0;
    const std::uint8_t state = twist_regime(k, ktr, limit, d);
    tw_regime_[k] = state;
    const std::size_t j = std::min(k, n - 2) - ef;
    if (state == 1) {
      tw_rhs_[j] += ktr * d;
      tw_diag_[j] += ktr;
    } else if (state != 0) {
      tw_rhs_[j] += state == 2 ? limit : -limit;
    }
  }
}

// Thomas algorithm on the symmetric tridiagonal system (off[j] couples j-1 and j), keeping the
// inverse pivots (the hand's Schur complement reuses them), and the update of the angles (at
// most half a radian). False when the update was not finite or was cut: nonlinear.
bool Rod::update_twist(std::size_t ef, std::size_t m, bool linear) {
  tw_inv_[0] = 1.0 / tw_diag_[0];
  for (std::size_t j = 1; j < m; ++j) tw_inv_[j] = 1.0 / (tw_diag_[j] - tw_off_[j] * tw_inv_[j - 1] * tw_off_[j]);
  twist_substitute(m);
  for (std::size_t j = 0; j < m; ++j) {
    const double step = tw_rhs_[j];
    if (!std::isfinite(step)) {
      linear = false;
      continue;
    }
    if (std::abs(step) > 0.5) linear = false;
    theta_[ef + j] -= std::clamp(step, -0.5, 0.5);
  }
  return linear;
}

// Every wall contact is in the friction regime the system was assembled with.
bool Rod::twist_regimes_same() const {
  bool same = true;
  for (std::size_t k = first_free_; k < x_.size() && same; ++k) {
    double ktr = 0.0, limit = 0.0, d = 0.0;
    same = twist_regime(k, ktr, limit, d) == tw_regime_[k];
  }
  return same;
}

// Torsional stiffness at the hand (the Schur complement of the last system on the clamp) and
// the torque the hand feels.
void Rod::hand_twist(double dt_s, std::size_t ef, std::size_t m) {
  const double c0 = gj_[ef] / (0.5 * rest_[ef]);
  for (std::size_t j = 0; j < m; ++j) tw_rhs_[j] = j == 0 ? 1.0 : 0.0;
  twist_substitute(m);
  law_.torsion_stiffness_mNmm_per_rad = std::max(0.0, c0 - c0 * c0 * tw_rhs_[0]);
  const double tau0 = theta_[ef] - theta_[ef - 1] + ref_twist_[ef];
  // As for the force: the solver's twist damping above the physical drag stays out of the hand.
  double numerical = 0.0;
  for (std::size_t j = 0; j < m; ++j) {
    const std::size_t e = ef + j;
    const double r = radius_[e + 1];
    numerical += (solver_drag(e + 1) - drag_per_mm_[e + 1] * voronoi_[e + 1]) * r * r / dt_s * (theta_[e] - theta_start_[e]);
  }
  hand_torque_mNmm_ = -c0 * tau0 - numerical;
}

}  // namespace cathbox::tool
