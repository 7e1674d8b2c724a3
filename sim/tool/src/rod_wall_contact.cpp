// Wall contacts: each free node's plane (and a second one in a crease of a meshed wall) from the
// wall probe, re-probed as nodes move; the hard limit of penetration after the solve; and, once
// the step is solved, the contact forces and the friction anchors (stick, or slip dragging the
// anchor along). The penalty and friction terms of the solve are in rod_energy.cpp.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "rod_node_contact.hpp"
#include "tool/mesh_wall.hpp"
#include "tool/rod.hpp"
#include "tool/wall_penalty.hpp"

namespace cathbox::tool {

bool Rod::refresh_contacts(const WallModel& wall, bool only_moved, bool keep_creases) {
  const std::size_t n = x_.size();
  bool active_changed = false;
  for (std::size_t k = first_free_; k < n; ++k) {
    NodeContact& c = node_contacts_[k];
    const double moved = glm::length(x_[k] - c.query_pos);
    if (c.clearance >= 0.0) {
      if (only_moved && moved < settings_.requery_move_mm) continue;
      if (!c.has_plane && moved < c.clearance - settings_.contact_margin_mm) continue;
    }
    WallProbe probe;
    probe.center_mm = x_[k];
    probe.radius_mm = radius_[k];
    probe.range_mm = settings_.query_range_mm;
    probe.margin_mm = settings_.contact_margin_mm;
    // A node widened past its section (an expanded stent filling its lumen) touches the ring
    // of the wall all round: its closest wall alone, no crease's second plane (every facet of
    // the ring would be one, and the search for it is most of such a node's probe); and not
    // the facets but the tube round the lumen's centreline where the wall knows one
    // (WallProbe::lumen_axis): the facets' planes it would flip between from one iteration to
    // the next.
    const bool widened = radius_[k] > 0.5 * section_at(k).outer_diameter_mm;
    probe.second_wall = !widened;
    probe.lumen_axis = widened;
    probe.depth_mm = insertion_mm_ - from_tip_[k];
    WallContact wc;
    c.query_pos = x_[k];
    active_changed = active_changed || c.active;
    if (wall.probe(probe, c.hint, wc) && std::isfinite(wc.distance_mm)) {
      if (c.has_plane && settings_.curved_wall_gap) estimate_curvature(c, wc);
      c.clearance = std::max(0.0, wc.distance_mm - radius_[k]);
      c.has_plane = wc.distance_mm - radius_[k] < settings_.contact_margin_mm;
      c.point = wc.point_mm;
      c.normal = wc.normal;
      // Within a solve a node keeps the crease's second plane the wall gave it while the
      // re-probe reports none (the other face no longer its closest feature there): dropped, the
      // node slid back into that face, took the plane again on the next re-probe and was pushed
      // out, every iteration (the stent retriever's push wire on the ICA's faceted bend:
      // docs/sim-tool/convergence.md, "A crease's second plane held within the solve").
      const bool keep = keep_creases && c.has_plane && c.has_second && !wc.has_second && glm::dot(c.normal2, wc.normal) < kCreaseSameFaceCos;
      c.has_second = c.has_plane && (wc.has_second || keep);
      if (!keep) {
        c.point2 = wc.second_point_mm;
        c.normal2 = wc.second_normal;
      }
      if (!c.has_second) c.active2 = false;
      c.segment = wc.segment;
    } else {
      c.clearance = settings_.query_range_mm;
      c.has_plane = false;
    }
    if (c.has_plane && !c.anchored) {
      c.anchored = true;
      c.anchor = x_[k];
      c.twist_anchor = theta_[std::min(k, n - 2)];
    } else if (!c.has_plane) {
      c.bend_per_mm = 0.0;
      c.bend2_per_mm = 0.0;
      c.anchored = false;
      c.active = false;
      c.has_second = false;
      c.active2 = false;
    }
  }
  if (refresh_edge_walls(wall, only_moved)) active_changed = true;
  return active_changed;
}

// The wall's curvature along the move of its closest point since the last probe of the same
// plane: the normal's turn along it over its length (a tube's 1 / R round it, 0 along it). Kept
// when the point hardly moved; only a concave wall (the lumen curving round the node) is kept.
namespace {
// A lumen of 0.5 mm radius: a meshed wall's normal jumps at a face's edge, which this bounds.
constexpr double kMaxCurvature_per_mm = 2.0;
constexpr double kSameDirection = 0.7;  // |cos| of two moves taken as along one direction
constexpr double kSquareEnough = 0.5;   // the least of the earlier direction kept across the new
}  // namespace

void Rod::estimate_curvature(NodeContact& c, const WallContact& wc) {
  const glm::dvec3 moved = wc.point_mm - c.point;
  const double len2 = glm::dot(moved, moved);
  if (len2 < 1e-8) return;
  const glm::dvec3 dir = moved - wc.normal * glm::dot(wc.normal, moved);
  const double dir_len = glm::length(dir);
  if (dir_len < 1e-4) return;
  const double kappa = std::clamp(glm::dot(wc.normal - c.normal, moved) / len2, 0.0, kMaxCurvature_per_mm);
  const double rho = kappa > 0.0 ? 1.0 / kappa - wc.distance_mm : 0.0;  // the centre's path
  const glm::dvec3 d = dir / dir_len;
  // A move across the last one's direction keeps that one's curvature as the second, made
  // square to the new direction and normal (dropped when little of it is left).
  if (std::abs(glm::dot(d, c.bend_dir)) < kSameDirection) {
    c.bend_dir2 = c.bend_dir;
    c.bend2_per_mm = c.bend_per_mm;
  }
  glm::dvec3 d2 = c.bend_dir2 - wc.normal * glm::dot(wc.normal, c.bend_dir2);
  d2 -= d * glm::dot(d, d2);
  const double d2_len = glm::length(d2);
  if (d2_len < kSquareEnough) {
    c.bend2_per_mm = 0.0;
  } else {
    c.bend_dir2 = d2 / d2_len;
  }
  c.bend_dir = d;
  c.bend_per_mm = rho > 0.0 ? 1.0 / rho : 0.0;
}

// The hard limit on both planes of a crease at once. Where the planes face each other (a fold
// of the wall: n1 . n2 < 0), the push off the second plane drives the node back into the first,
// by |n1 . n2| of that push, and its contact would read the penalty of the overshoot (tens of
// newtons from a millimetre). Alternating the two projections converges on the corner of the
// two half-spaces, the overshoot shrinking by (n1 . n2)^2 a round (<= 1/4 for the creases a
// meshed wall reports: MeshWall takes no second plane facing the first by more than that).
void Rod::limit_penetration() {
  const std::size_t n = x_.size();
  compressed_ = false;
  jammed_ = false;
  constexpr int kCreaseRounds = 16;
  const auto limit_both_planes = [this](std::size_t k, double allowed) {
    const NodeContact& nc = node_contacts_[k];
    for (int round = 0; round < kCreaseRounds; ++round) {
      const double phi = plane_gap(k);
      if (phi <= allowed) return;
      x_[k] -= nc.normal * (phi - allowed);
      const double phi2 = second_gap(k);
      if (phi2 > allowed) x_[k] -= nc.normal2 * (phi2 - allowed);
    }
  };
  limit_edge_walls();
  for (std::size_t k = first_free_; k < n; ++k) {
    NodeContact& nc = node_contacts_[k];
    if (nc.has_plane) {
      const double allowed = settings_.max_penetration_ratio * radius_[k];
      const double phi = plane_gap(k);
      if (phi > allowed) x_[k] -= nc.normal * (phi - allowed);
      if (phi > 0.0) nc.active = true;
      if (nc.has_second) {
        const double phi2 = second_gap(k);
        if (phi2 > allowed) x_[k] -= nc.normal2 * (phi2 - allowed);
        if (phi2 > 0.0) nc.active2 = true;
        if (phi2 > allowed) limit_both_planes(k, allowed);
      }
    }
    if (k == 0) continue;
    const double length = glm::length(x_[k] - x_[k - 1]);
    if (length < rest_[k - 1] * (1.0 - settings_.buckling_strain)) compressed_ = true;
    if (length < rest_[k - 1] * (1.0 - settings_.warm_start_strain)) jammed_ = true;
  }
}

void Rod::finish_contacts() {
  const std::size_t n = x_.size();
  contacts_.clear();
  const WallPenalty wall(settings_);
  for (std::size_t k = first_free_; k < n; ++k) {
    NodeContact& nc = node_contacts_[k];
    // The normal forces are the step's: a node with no plane at its end has none. Left from
    // its last contact, the next step that found it a plane held it there (Rod::start_solve's
    // active set), the quadratic continued below 0 pulling it from 0.15 mm off: 3 N on the dense
    // case's withdrawn pusher, -1,104.6 mN for one tick on its clamp (scripts/robustness, x0.995).
    if (!nc.has_plane) {
      nc.normal_force = 0.0;
      nc.normal_force2 = 0.0;
      continue;
    }
    const double kt = wall_stick_mN_per_mm(k);
    add_second_contact(k);
    const double phi = plane_gap(k);
    const std::size_t e = std::min(k, n - 2);
    if (phi <= 0.0) {
      nc.anchor = x_[k];
      nc.twist_anchor = theta_[e];
      nc.normal_force = 0.0;
      continue;
    }
    const double normal_force = wall.force_mN(phi);
    const glm::dmat3 pt = glm::dmat3(1.0) - glm::outerProduct(nc.normal, nc.normal);
    const glm::dvec3 slip = pt * (x_[k] - nc.anchor);
    const double slip_len = glm::length(slip);
    const double limit = friction_at(k) * normal_force;
    glm::dvec3 friction(0.0);
    if (kt * slip_len > limit && slip_len > 0.0) {
      const glm::dvec3 s = slip / slip_len;
      nc.anchor = x_[k] - s * (limit / kt);
      friction = -s * limit;
    } else {
      friction = -slip * kt;
    }
    const double r = radius_[k];
    const double ktr = kt * r * r;
    const double tlimit = limit * r;
    const double d = theta_[e] - nc.twist_anchor;
    if (ktr * std::abs(d) > tlimit) nc.twist_anchor = theta_[e] - (d > 0.0 ? tlimit : -tlimit) / ktr;
    nc.normal_force = normal_force;
    RodContact out;
    out.node = static_cast<std::uint32_t>(k);
    out.point_mm = x_[k] + nc.normal * (r - phi);
    out.normal = nc.normal;
    out.normal_force_mN = normal_force;
    out.friction_mN = friction;
    out.segment = nc.segment;
    contacts_.push_back(out);
  }
  add_edge_wall_contacts();
}

// The contact on the second plane of node k (a crease of a meshed wall): normal force only.
void Rod::add_second_contact(std::size_t k) {
  NodeContact& nc = node_contacts_[k];
  nc.normal_force2 = nc.has_second ? WallPenalty(settings_).force_mN(second_gap(k)) : 0.0;
  if (nc.normal_force2 > 0.0) {
    RodContact second;
    second.node = static_cast<std::uint32_t>(k);
    second.point_mm = x_[k] + nc.normal2 * (radius_[k] - second_gap(k));
    second.normal = nc.normal2;
    second.normal_force_mN = nc.normal_force2;
    second.segment = nc.segment;
    contacts_.push_back(second);
  }
}

}  // namespace cathbox::tool
