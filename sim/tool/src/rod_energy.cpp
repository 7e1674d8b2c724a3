// The step's energy (stretching, bending, drag, loads, grip, wall penalty and friction, the
// penalty of other rods) and, in one pass along the rod, its gradient and Gauss-Newton Hessian
// for the Newton solve (rod_newton.cpp).
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "rod_newton.hpp"
#include "rod_node_contact.hpp"
#include "tool/banded_cholesky.hpp"
#include "tool/rod.hpp"
#include "tool/wall_penalty.hpp"

namespace cathbox::tool {

// An inflated balloon's grip: an elastic-plastic anchor that slips beyond its limit.
[[gnu::always_inline]] inline void Rod::add_grip_terms(std::size_t k, glm::dmat3& h) {
  const glm::dmat3 identity(1.0);
  const double kg = settings_.stick_stiffness_mN_per_mm();
  const glm::dvec3 rel = x_[k] - grip_anchor_[k];
  const double rel_len = glm::length(rel);
  const double limit = grip_limit_[k];
  if (kg * rel_len <= limit) {
    add_grad(k, rel * kg);
    h += identity * kg;
    energy_ += 0.5 * kg * rel_len * rel_len;
  } else {
    const glm::dvec3 ru = rel / rel_len;
    add_grad(k, ru * limit);
    h += (limit / rel_len) * (identity - glm::outerProduct(ru, ru));
    energy_ += limit * rel_len - 0.5 * limit * limit / kg;
  }
}

// The wall's penalty on node k's active planes, and the Coulomb friction (a stick spring with a
// slip limit) on its first plane.
[[gnu::always_inline]] inline void Rod::add_wall_terms(std::size_t k, glm::dmat3& h) {
  const glm::dmat3 identity(1.0);
  const WallPenalty wall(settings_);
  const double kt = wall_stick_mN_per_mm(k);
  const NodeContact& nc = node_contacts_[k];
  if (nc.has_plane && nc.active2) {
    const double phi2 = second_gap(k);
    add_grad(k, nc.normal2 * wall.gradient_mN(phi2));
    h += wall.stiffness_mN_per_mm(phi2) * glm::outerProduct(nc.normal2, nc.normal2);
    energy_ += wall.energy(phi2);
  }
  if (!nc.has_plane || !nc.active) return;
  const double phi = plane_gap(k);
  const glm::dmat3 nn = glm::outerProduct(nc.normal, nc.normal);
  const double f = wall.gradient_mN(phi);
  if (!nc.curved()) {
    add_grad(k, nc.normal * f);
    h += wall.stiffness_mN_per_mm(phi) * nn;
  } else {
    // On a concave wall: the gap's gradient turns with the wall, and a pressed node (f > 0) is
    // held along the curvature by f / rho.
    const glm::dvec3 g = gap_normal(k);
    add_grad(k, g * f);
    h += wall.stiffness_mN_per_mm(phi) * glm::outerProduct(g, g) +
         std::max(0.0, f) * (nc.bend_per_mm * glm::outerProduct(nc.bend_dir, nc.bend_dir) +
                             nc.bend2_per_mm * glm::outerProduct(nc.bend_dir2, nc.bend_dir2));
  }
  energy_ += wall.energy(phi);
  const double mu = friction_at(k);
  if (!(mu > 0.0)) return;
  const glm::dmat3 pt = identity - nn;
  const glm::dvec3 slip = pt * (x_[k] - nc.anchor);
  const double slip_len = glm::length(slip);
  // The slip limit uses the normal force of the previous step, so within a step friction
  // is a fixed convex potential and the iterations converge.
  const double limit = mu * nc.normal_force;
  friction_limit_[k] = limit;
  if (kt * slip_len <= limit) {
    add_grad(k, slip * kt);
    h += kt * pt;
    energy_ += 0.5 * kt * slip_len * slip_len;
  } else {
    energy_ += limit * slip_len - 0.5 * limit * limit / kt;
    const glm::dvec3 sd = slip / slip_len;
    add_grad(k, sd * limit);
    h += (limit / slip_len) * (pt - glm::outerProduct(sd, sd));
  }
}

// Edge k's stretching (gradient and energy, node to node) and, for the Hessian, its c_e P_e with
// w_sum the bending weights of its two vertices. u and inv come back as the edge's tangent and
// inverse length as its bending sees them: the clamp chord's on the hinge edge (the clamp's hinge
// at the entry point, Rod::clamp_chord), whose block is then the stretching's on P_e plus the
// bending's on the chord's projector.
[[gnu::always_inline]] inline void Rod::add_edge_terms(std::size_t k, double w_sum, bool hinge, bool hessian, glm::dvec3& u,
                                                       double& inv, double& ks, glm::dmat3& pc) {
  const glm::dmat3 identity(1.0);
  const glm::dvec3 e = x_[k + 1] - x_[k];
  const double len = std::max(glm::length(e), 1e-12);
  inv = 1.0 / len;
  u = e * inv;
  ks = axial_k_[k];
  const glm::dvec3 f = u * (ks * (len - rest_[k]));
  energy_ += 0.5 * ks * (len - rest_[k]) * (len - rest_[k]);
  add_grad(k + 1, f);
  add_grad(k, -f);
  if (!hinge) {
    if (hessian) pc = (identity - glm::outerProduct(u, u)) * (ks * std::max(0.0, 1.0 - rest_[k] * inv) - ks + w_sum * (inv * inv));
    return;
  }
  const glm::dvec3 chord = clamp_chord();
  const double inv_b = 1.0 / std::max(glm::length(chord), 1e-12);
  const glm::dvec3 u_b = chord * inv_b;
  if (hessian) {
    pc = (identity - glm::outerProduct(u, u)) * (ks * std::max(0.0, 1.0 - rest_[k] * inv) - ks) +
         (identity - glm::outerProduct(u_b, u_b)) * (w_sum * (inv_b * inv_b));
  }
  u = u_b;
  inv = inv_b;
}

// The free node k's own terms: drag, loads, grip, wall penalty and friction. Returns its block
// on the Hessian's diagonal (the gradient and the energy take the terms as they go).
[[gnu::always_inline]] inline glm::dmat3 Rod::node_terms(std::size_t k) {
  const glm::dmat3 identity(1.0);
  const double cd = drag_k_[k];
  const glm::dvec3 moved = x_[k] - x_start_[k];
  const glm::dvec3 load = load_[k] + coupling_[k] + (k < twist_load_.size() ? twist_load_[k] : glm::dvec3(0.0));
  add_grad(k, moved * cd - load);
  glm::dmat3 h = identity * cd;
  energy_ += 0.5 * cd * glm::dot(moved, moved) - glm::dot(load, x_[k]);
  if (grip_limit_[k] > 0.0) add_grip_terms(k, h);
  friction_limit_[k] = 0.0;
  add_wall_terms(k, h);
  return h;
}

// Gradient, energy and Hessian in one pass along the rod: each edge's length and tangent
// once (its stretching and the bending at the vertices either side share them), and each
// block row written as soon as its last term is known. The Gauss-Newton Hessian in terms of
// the edge projectors P_e = I - t_e t_e^T:
//   stretching of edge e: ks_e I + (ks'_e - ks_e) P_e, ks = EA / rest, ks' = ks max(0, 1 - rest / len);
//   bending at vertex i (edges a = i - 1, b = i): w J^T J with J = [P_a / l_a, -(P_a / l_a + P_b / l_b),
//   P_b / l_b] on nodes i - 1, i, i + 1, whose blocks are w P_a / l_a^2, w P_b / l_b^2 and
//   multiples of M_i = P_b P_a = I - t_a t_a^T - t_b t_b^T + (t_a . t_b) t_b t_a^T.
// Block row k is then
//   A(k, k)     = nodal_k + (ks_k + ks_{k-1}) I + c_k P_k + c_{k-1} P_{k-1} + g_k (M_k + M_k^T),
//   A(k, k - 1) = -ks_{k-1} I - c_{k-1} P_{k-1} - g_k M_k - g_{k-1} M_{k-1},
//   A(k, k - 2) = g_{k-1} M_{k-1},
// with c_e = ks'_e - ks_e + (w_e + w_{e+1}) / l_e^2 and g_i = w_i / (l_{i-1} l_i) (w = 0 off the
// bending vertices first_ + 1 .. n - 2).
void Rod::assemble(bool hessian) {
  const std::size_t n = x_.size();
  const std::size_t dofs = 3 * (n - first_);
  std::fill(grad_.begin(), grad_.begin() + static_cast<std::ptrdiff_t>(dofs), 0.0);
  energy_ = 0.0;
  const glm::dmat3 identity(1.0);
  const glm::dmat3 zero(0.0);
  const auto vertex = [&](std::size_t i) { return i >= first_ + 1 && i + 1 < n; };
  if (hessian) matrix_->resize(n - first_);

  // Edge k - 1 and vertex k - 1, carried from the last node.
  glm::dvec3 u_prev(0.0);
  double inv_prev = 1.0;  // 1 / l_{k-1}
  glm::dmat3 pc_prev(0.0), m_prev(0.0);
  double ks_prev = 0.0, g_prev = 0.0;
  double w = 0.0;  // vertex k's bending weight (first_ is no vertex)
  const std::size_t hinge_edge = clamp_shift_mm_ > 0.0 ? first_ + 1 : n;  // bends on clamp_chord()
  for (std::size_t k = first_; k < n; ++k) {
    // Edge k: node k -> k + 1 (its stretching, and c_e P_e; u, inv as the bending sees it).
    glm::dvec3 u(0.0);
    double inv = 1.0, ks = 0.0;
    glm::dmat3 pc(0.0);
    const double w_next = vertex(k + 1) ? bend_w_[k + 1] : 0.0;
    if (k + 1 < n) add_edge_terms(k, w + w_next, k == hinge_edge, hessian, u, inv, ks, pc);
    // Vertex k, between edges k - 1 and k.
    double g = 0.0;
    glm::dmat3 m(0.0);
    if (vertex(k)) {
      const glm::dvec3 r = bend_residual(k, u_prev, u);
      const double ca = w * inv_prev;
      const double cb = w * inv;
      const glm::dvec3 ga = (u_prev * glm::dot(u_prev, r) - r) * ca;  // w ja^T r, ja = -P_a / l_a
      const glm::dvec3 gb = (r - u * glm::dot(u, r)) * cb;            // w jb^T r, jb = P_b / l_b
      add_grad(k - 1, -ga);
      add_grad(k, ga - gb);
      add_grad(k + 1, gb);
      energy_ += 0.5 * w * glm::dot(r, r);
      if (hessian) {
        g = ca * inv;
        m = identity - glm::outerProduct(u_prev, u_prev) - glm::outerProduct(u, u) +
            glm::outerProduct(u, u_prev) * glm::dot(u_prev, u);
      }
    }
    // Wall contacts, friction, drag and loads on the free nodes: one block on the diagonal.
    const glm::dmat3 h = k >= first_free_ ? node_terms(k) : zero;
    if (hessian) {
      const glm::dmat3 diag = h + identity * (ks + ks_prev) + pc + pc_prev + (m + glm::transpose(m)) * g;
      const glm::dmat3 sub1 = -(identity * ks_prev + pc_prev + m * g + m_prev * g_prev);
      matrix_->set_row(k - first_, diag, sub1, m_prev * g_prev);
    }
    u_prev = u;
    inv_prev = inv;
    pc_prev = pc;
    m_prev = m;
    ks_prev = ks;
    g_prev = g;
    w = w_next;
  }

  add_edge_contact_terms(hessian);
  add_edge_wall_terms(hessian);
  add_twist_stiffness(hessian);
}

double Rod::energy() const {
  // The energy whose gradient assemble() builds, with the friction limits of the last assembly.
  const std::size_t n = x_.size();
  double e = 0.0;
  glm::dvec3 u_prev(0.0);  // edge k - 1's tangent
  for (std::size_t k = first_; k + 1 < n; ++k) {
    const glm::dvec3 edge = x_[k + 1] - x_[k];
    const double len = std::max(glm::length(edge), 1e-12);
    const double stretch = len - rest_[k];
    e += 0.5 * axial_k_[k] * stretch * stretch;
    glm::dvec3 u = edge * (1.0 / len);
    if (clamp_shift_mm_ > 0.0 && k == first_ + 1) u = glm::normalize(clamp_chord());  // bends on it
    if (k >= first_ + 1) {
      const glm::dvec3 r = bend_residual(k, u_prev, u);
      e += 0.5 * bend_w_[k] * glm::dot(r, r);
    }
    u_prev = u;
  }
  const double kc = settings_.contact_stiffness_mN_per_mm;
  const double kt = kc * settings_.stick_stiffness_ratio;
  const WallPenalty wall(settings_);
  for (const EdgeContact& ec : edge_contacts_) {
    const double phi = edge_gap(ec);
    if (phi > 0.0) e += 0.5 * edge_stiffness(ec, kc) * phi * phi;
  }
  for (std::size_t k = first_free_; k < n; ++k) {
    const glm::dvec3 moved = x_[k] - x_start_[k];
    const glm::dvec3 twist = k < twist_load_.size() ? twist_load_[k] : glm::dvec3(0.0);
    e += 0.5 * drag_k_[k] * glm::dot(moved, moved) - glm::dot(load_[k] + coupling_[k] + twist, x_[k]);
    if (grip_limit_[k] > 0.0) {
      const double len = glm::length(x_[k] - grip_anchor_[k]);
      const double limit = grip_limit_[k];
      e += kt * len <= limit ? 0.5 * kt * len * len : limit * len - 0.5 * limit * limit / kt;
    }
    const NodeContact& nc = node_contacts_[k];
    if (!nc.has_plane) continue;
    if (nc.active2) e += wall.energy(second_gap(k));
    if (!nc.active) continue;
    e += wall.energy(plane_gap(k));
    const double limit = friction_limit_[k];
    if (limit <= 0.0) continue;
    const glm::dvec3 rel = x_[k] - nc.anchor;
    const double slip = glm::length(rel - nc.normal * glm::dot(nc.normal, rel));
    const double ks = wall_stick_mN_per_mm(k);
    e += ks * slip <= limit ? 0.5 * ks * slip * slip : limit * slip - 0.5 * limit * limit / ks;
  }
  return e + edge_wall_energy() + twist_stiffness_energy();
}

}  // namespace cathbox::tool
