// The wall against the rod's edges (RodSettings::edge_wall_contact). A node's contact holds the
// node's ball out of the wall; a sharp convex wall (a carina's flow divider, a sac's neck) can
// still pass between two nodes and through the edge joining them. Each free edge whose nodes'
// wall normals turn against it enough for a bulge (a convex wall's bound, from the nodes' own
// probes: no probe for an edge along a tube's side) and whose middle is near the wall (its ball
// not inside the wall-free ball round either node's last probe) is probed at its middle, whose
// closest wall the wall model gives exactly; where the wall there is
// nearer than the nodes' mean distance by kBulge radii (it bulges between them), a one-sided
// plane at that wall point holds the middle (s = 1/2), its penalty shared by the two nodes by the
// barycentric weights 1 - s and s, in the nodes' active-set machinery (joins, leaving, the hard
// limit after the solve). On a flat or concave wall the middle is as far as or farther than the
// nodes' mean, so the nodes' own planes stay the whole contact and no force is counted twice; a
// wall point nearest an end (projecting within kEnd of it) is that node's. Held at the wall
// point's projection instead, the middle's plane reached past a carina's ridge into the other
// child (docs/sim-tool/convergence.md, "The wall against edges"). Normal force only (no friction
// on an edge's plane).
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "rod_newton.hpp"
#include "rod_node_contact.hpp"
#include "tool/rod.hpp"
#include "tool/wall_penalty.hpp"

namespace cathbox::tool {

namespace {
constexpr double kEnd = 0.05;    // a wall point nearer an end than this (of the edge) is the node's
// Radii: a sharp feature's bulge; at 0.025 the shaft's edges in every bend took planes, which
// moved a curved tip's converged slip (RodValidation.CurvedTip...) and tripled coiling's shares.
constexpr double kBulge = 0.25;
// Of kBulge: the least bound on the bulge (from the nodes' normals) for which the middle is
// probed; below one, for normals up to a re-probe's move old and walls not quite convex.
constexpr double kTurnShare = 0.5;

// The penetration an edge's plane allows at its point s: the nodes' ratio of its radius there.
double edge_allowed_mm(double ratio, double radius_a, double radius_b, double s) {
  return ratio * (radius_a * (1.0 - s) + radius_b * s);
}
}  // namespace

// A node's centre distance to the wall, at least (its own plane's, else its probed clearance
// less its move since).
double Rod::node_wall_distance(std::size_t j) const {
  const NodeContact& nc = node_contacts_[j];
  if (nc.has_plane) return radius_[j] - plane_gap(j);
  return radius_[j] + std::max(0.0, nc.clearance - glm::length(x_[j] - nc.query_pos));
}

// The nodes' last probes bound the bulge before the middle is probed. Where the wall's solid is
// convex (a ridge, a carina's apex) the distance d to it is a convex function whose gradient is
// -n (n the wall normal, out of the lumen), so d(mid) >= d_j - n_j . (mid - x_j) at either node
// and the middle is nearer than the nodes' mean by at most e . (n_k - n_k+1) / 4 (e the edge
// from k): the normal must turn against the edge's direction across it. A wall along the edge (a
// tube's side, a sac's inner face) turns it the other way or hardly at all, and its edges are not
// probed. A node whose probe found no wall in range has no normal to tell. A node widened past
// its section (an expanded stent filling its lumen) touches the wall all round, its closest
// point anywhere on the ring: its edges are the nodes' alone.
bool Rod::edge_may_bulge(std::size_t k) const {
  const NodeContact& a = node_contacts_[k];
  const NodeContact& b = node_contacts_[k + 1];
  const double range = settings_.query_range_mm;
  const double r = 0.5 * (radius_[k] + radius_[k + 1]);
  const bool known = a.clearance >= 0.0 && a.clearance < range && b.clearance >= 0.0 && b.clearance < range;
  if (known && 0.25 * glm::dot(x_[k + 1] - x_[k], a.normal - b.normal) < kTurnShare * kBulge * r) return false;
  const auto widened = [&](std::size_t j) { return radius_[j] > 0.5 * section_at(j).outer_diameter_mm; };
  return !widened(k) && !widened(k + 1);
}

bool Rod::refresh_edge_walls(const WallModel& wall, bool only_moved) {
  edge_planes_ = 0;
  if (!settings_.edge_wall_contact) return false;
  bool active_changed = false;
  for (std::size_t k = first_free_; k + 1 < x_.size(); ++k) {
    if (refresh_edge_wall(wall, k, only_moved)) active_changed = true;
    if (node_contacts_[k].edge.has_plane) ++edge_planes_;
  }
  return active_changed;
}

// Edge k's plane, probed again where it may have changed; true when an active plane was let go
// or probed again (the active set may change).
bool Rod::refresh_edge_wall(const WallModel& wall, std::size_t k, bool only_moved) {
  NodeContact::EdgeWall& ew = node_contacts_[k].edge;
  if (!ew.has_plane && !edge_may_bulge(k)) {
    if (ew.clearance >= 0.0) ew = NodeContact::EdgeWall{.hint = ew.hint};
    return false;
  }
  const double margin = settings_.contact_margin_mm;
  const glm::dvec3 mid = 0.5 * (x_[k] + x_[k + 1]);
  const double r = 0.5 * (radius_[k] + radius_[k + 1]);
  const double moved = glm::length(mid - ew.query_mid);
  if (ew.clearance >= 0.0) {
    if (only_moved && moved < settings_.requery_move_mm) return false;
    if (!ew.has_plane && moved < ew.clearance - margin) return false;
  }
  // The middle's ball widened by the margin inside the wall-free ball a node's last probe
  // found (its radius plus clearance round where it was probed): no wall near the middle.
  const auto inside_free_ball = [&](std::size_t j) {
    const NodeContact& nc = node_contacts_[j];
    return nc.clearance > 0.0 && glm::length(mid - nc.query_pos) + r + margin <= radius_[j] + nc.clearance;
  };
  const bool was_active = ew.active;
  if (inside_free_ball(k) || inside_free_ball(k + 1)) {
    ew = NodeContact::EdgeWall{.hint = ew.hint};
    return was_active;
  }
  WallProbe probe;
  probe.center_mm = mid;
  probe.radius_mm = r;
  probe.range_mm = settings_.query_range_mm;
  probe.margin_mm = margin;
  probe.second_wall = false;
  probe.depth_mm = insertion_mm_ - 0.5 * (from_tip_[k] + from_tip_[k + 1]);
  WallContact wc;
  ew.query_mid = mid;
  bool plane = false;
  if (wall.probe(probe, ew.hint, wc) && std::isfinite(wc.distance_mm)) {
    ew.clearance = std::max(0.0, wc.distance_mm - r);
    const glm::dvec3 e = x_[k + 1] - x_[k];
    const double len2 = glm::dot(e, e);
    const double s = len2 > 0.0 ? std::clamp(glm::dot(wc.point_mm - x_[k], e) / len2, 0.0, 1.0) : 0.5;
    const double mean = 0.5 * (node_wall_distance(k) + node_wall_distance(k + 1));
    const bool bulges = ew.has_plane || wc.distance_mm < mean - kBulge * r;  // kept while near
    plane = wc.distance_mm - r < margin && s >= kEnd && s <= 1.0 - kEnd && bulges;
    if (plane) {
      ew.s = 0.5;  // the probed point
      ew.point = wc.point_mm;
      ew.normal = wc.normal;
      ew.segment = wc.segment;
    }
  } else {
    ew.clearance = settings_.query_range_mm;
  }
  ew.has_plane = plane;
  if (!plane) {
    ew.active = false;
    ew.normal_force = 0.0;
  }
  return was_active;
}

// The penalty of edge k's active plane: energy, gradient and (Gauss-Newton) Hessian blocks.
void Rod::add_edge_wall_term(std::size_t k, bool hessian) {
  const NodeContact::EdgeWall& ew = node_contacts_[k].edge;
  if (!ew.has_plane || !ew.active) return;
  const WallPenalty wall(settings_);
  const double phi = edge_wall_gap(k);
  const double f = wall.gradient_mN(phi);
  const double wa = 1.0 - ew.s;
  const double wb = ew.s;
  energy_ += wall.energy(phi);
  add_grad(k, ew.normal * (f * wa));
  add_grad(k + 1, ew.normal * (f * wb));
  if (!hessian) return;
  const rod_detail::BlockAdder add{*matrix_, first_, true};
  const glm::dmat3 nn = wall.stiffness_mN_per_mm(phi) * glm::outerProduct(ew.normal, ew.normal);
  add(k, k, nn * (wa * wa));
  add(k + 1, k + 1, nn * (wb * wb));
  add(k + 1, k, nn * (wa * wb));
}

void Rod::add_edge_wall_terms(bool hessian) {
  if (edge_planes_ == 0) return;
  for (std::size_t k = first_free_; k + 1 < x_.size(); ++k) add_edge_wall_term(k, hessian);
}

double Rod::edge_wall_energy() const {
  double e = 0.0;
  if (edge_planes_ == 0) return e;
  const WallPenalty wall(settings_);
  for (std::size_t k = first_free_; k + 1 < x_.size(); ++k) {
    const NodeContact::EdgeWall& ew = node_contacts_[k].edge;
    if (ew.has_plane && ew.active) e += wall.energy(edge_wall_gap(k));
  }
  return e;
}

// Edges off their plane that the Newton step would carry into it join the active set (bit 2
// of joined_ at the edge's first node).
bool Rod::join_edge_walls() {
  bool joined = false;
  if (edge_planes_ == 0) return joined;
  for (std::size_t k = first_free_; k + 1 < x_.size(); ++k) {
    NodeContact::EdgeWall& ew = node_contacts_[k].edge;
    if (!ew.has_plane || ew.active) continue;
    const std::size_t d = 3 * (k - first_);
    const glm::dvec3 step = glm::dvec3(delta_[d], delta_[d + 1], delta_[d + 2]) * (1.0 - ew.s) +
                            glm::dvec3(delta_[d + 3], delta_[d + 4], delta_[d + 5]) * ew.s;
    if (edge_wall_gap(k) + glm::dot(ew.normal, step) > 0.0) {
      ew.active = true;
      joined = true;
      joined_[k] |= 4;
    }
  }
  return joined;
}

// As for the nodes: an edge its plane would have to pull leaves; one carried into it joins.
void Rod::update_edge_wall_set(Newton& s) {
  if (edge_planes_ == 0) return;
  for (std::size_t k = first_free_; k + 1 < x_.size(); ++k) {
    NodeContact::EdgeWall& ew = node_contacts_[k].edge;
    if (!ew.has_plane) continue;
    const double phi = edge_wall_gap(k);
    const double allowed = edge_allowed_mm(settings_.max_penetration_ratio, radius_[k], radius_[k + 1], ew.s);
    if (ew.active && phi < -1e-9) {
      ew.active = false;
      s.refactor = true;
    } else if (!ew.active && phi > 0.0) {
      ew.active = true;
      s.refactor = true;
      s.entered = s.entered || phi > 0.01 * allowed;
    } else {
      s.deep = s.deep || (ew.active && phi > allowed);
    }
  }
}

// The hard limit after the solve: an edge past it is moved out along its normal by the least
// move of its two nodes that does it (each by its weight).
void Rod::limit_edge_walls() {
  for (std::size_t k = first_free_; edge_planes_ > 0 && k + 1 < x_.size(); ++k) {
    NodeContact::EdgeWall& ew = node_contacts_[k].edge;
    if (!ew.has_plane) continue;
    const double phi = edge_wall_gap(k);
    const double allowed = edge_allowed_mm(settings_.max_penetration_ratio, radius_[k], radius_[k + 1], ew.s);
    if (phi > 0.0) ew.active = true;
    if (phi <= allowed) continue;
    const double wa = 1.0 - ew.s;
    const double wb = ew.s;
    const double per = (phi - allowed) / (wa * wa + wb * wb);
    x_[k] -= ew.normal * (per * wa);
    x_[k + 1] -= ew.normal * (per * wb);
  }
}

// After the step: each pressed edge's contact, reported at its nearer node.
void Rod::add_edge_wall_contacts() {
  if (edge_planes_ == 0) return;  // an edge without a plane keeps no force (refresh_edge_walls)
  const WallPenalty wall(settings_);
  for (std::size_t k = first_free_; k + 1 < x_.size(); ++k) {
    NodeContact::EdgeWall& ew = node_contacts_[k].edge;
    const double phi = ew.has_plane ? edge_wall_gap(k) : 0.0;
    ew.normal_force = wall.force_mN(phi);
    if (!(ew.normal_force > 0.0)) continue;
    const double r = radius_[k] * (1.0 - ew.s) + radius_[k + 1] * ew.s;
    RodContact out;
    out.node = static_cast<std::uint32_t>(ew.s < 0.5 ? k : k + 1);
    out.point_mm = x_[k] * (1.0 - ew.s) + x_[k + 1] * ew.s + ew.normal * (r - phi);
    out.normal = ew.normal;
    out.normal_force_mN = ew.normal_force;
    out.segment = ew.segment;
    contacts_.push_back(out);
  }
}

}  // namespace cathbox::tool
