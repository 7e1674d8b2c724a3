#pragma once
// Private to the rod's sources: a node's wall contact (its plane or two, its friction anchors,
// its probe hint) and the penetration of a node or an edge into its planes. Inline: the
// assembly, the energy and the active set read the gaps per node and iteration.
#include <cstdint>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "tool/rod.hpp"
#include "tool/wall_model.hpp"

namespace cathbox::tool {

struct Rod::NodeContact {
  bool has_plane = false;
  bool active = false;  // held on its plane in this step's solve (active set)
  bool has_second = false;  // a second plane (crease of a meshed wall): normal force only
  bool active2 = false;
  glm::dvec3 point2{0.0};
  glm::dvec3 normal2{0.0};
  double normal_force2 = 0.0;
  glm::dvec3 point{0.0};
  glm::dvec3 normal{0.0};
  std::int32_t segment = -1;
  WallHint hint;
  glm::dvec3 query_pos{0.0};
  double clearance = -1.0;  // node surface clearance when last probed; < 0: probe again
  bool anchored = false;
  glm::dvec3 anchor{0.0};
  double twist_anchor = 0.0;
  double normal_force = 0.0;
  glm::dvec3 friction{0.0};
  // The wall's curvature along one tangent direction, from the last two probes of this plane
  // (the normal's turn over the point's move), as the curvature of the path on which the node's
  // centre keeps its gap (1 / rho, rho from the centre to the wall's centre of curvature): the
  // gap is the plane's plus rho^-1 (t . u)^2 / 2, u the move since the probe. One plane alone
  // lets a node pressed on a concave wall slide along its tangent without going deeper.
  glm::dvec3 bend_dir{0.0};
  double bend_per_mm = 0.0;
  // The curvature along an earlier probe's direction, across bend_dir (a sphere's cap curves
  // both ways, a tube's round it alone): the gap is the plane's plus both terms.
  glm::dvec3 bend_dir2{0.0};
  double bend2_per_mm = 0.0;
  [[nodiscard]] bool curved() const { return bend_per_mm != 0.0 || bend2_per_mm != 0.0; }
  // The wall against the edge from this node to the next (rod_edge_wall.cpp): a one-sided plane
  // at the wall's closest point to the edge's middle, holding the edge's point s (its middle),
  // taken only where the wall bulges between the nodes (nearer the middle than the nodes' mean),
  // so a flat or concave wall stays the nodes' own.
  struct EdgeWall {
    bool has_plane = false;
    bool active = false;
    double s = 0.5;
    glm::dvec3 point{0.0};
    glm::dvec3 normal{0.0};
    glm::dvec3 query_mid{0.0};
    double clearance = -1.0;  // the middle's surface clearance when last probed; < 0: probe again
    double normal_force = 0.0;
    std::int32_t segment = -1;
    WallHint hint;
  } edge;
};

inline double Rod::plane_gap(std::size_t k) const {
  const NodeContact& nc = node_contacts_[k];
  const double flat = glm::dot(nc.normal, x_[k] - nc.point) + radius_[k];
  if (!nc.curved()) return flat;
  const glm::dvec3 u = x_[k] - nc.query_pos;
  const double along = glm::dot(nc.bend_dir, u);
  const double across = glm::dot(nc.bend_dir2, u);
  return flat + 0.5 * (nc.bend_per_mm * along * along + nc.bend2_per_mm * across * across);
}

// The gradient of plane_gap(k): the normal, turned along the wall's curvature.
inline glm::dvec3 Rod::gap_normal(std::size_t k) const {
  const NodeContact& nc = node_contacts_[k];
  if (!nc.curved()) return nc.normal;
  const glm::dvec3 u = x_[k] - nc.query_pos;
  return nc.normal + nc.bend_dir * (nc.bend_per_mm * glm::dot(nc.bend_dir, u)) +
         nc.bend_dir2 * (nc.bend2_per_mm * glm::dot(nc.bend_dir2, u));
}

inline double Rod::second_gap(std::size_t k) const {
  const NodeContact& nc = node_contacts_[k];
  return glm::dot(nc.normal2, x_[k] - nc.point2) + radius_[k];
}

// Penetration of edge k -> k + 1's point s (its radius there) into the edge's wall plane.
inline double Rod::edge_wall_gap(std::size_t k) const {
  const NodeContact::EdgeWall& ew = node_contacts_[k].edge;
  const glm::dvec3 p = x_[k] * (1.0 - ew.s) + x_[k + 1] * ew.s;
  return glm::dot(ew.normal, p - ew.point) + radius_[k] * (1.0 - ew.s) + radius_[k + 1] * ew.s;
}

inline double Rod::edge_gap(const EdgeContact& c) const {
  const glm::dvec3 p = x_[c.edge] * (1.0 - c.s) + x_[c.edge + 1] * c.s;
  return c.offset_mm - glm::dot(c.normal, p);
}

}  // namespace cathbox::tool
