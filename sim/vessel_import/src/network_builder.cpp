#include "vessel_import/network_builder.hpp"

#include <cstddef>
#include <map>
#include <vector>

#include <glm/geometric.hpp>

#include "network_cleanup.hpp"
#include "network_graph.hpp"
#include "network_orient.hpp"
#include "network_segments.hpp"

namespace cathbox::vessel_import {
namespace {

using detail::CenterlinePoint;
using detail::contract_short_branches;
using detail::Graph;
using detail::join_chains;
using detail::join_near_ends;
using detail::kNone;
using detail::Location;
using detail::merge_collapsed;
using detail::nearest_free_end;
using detail::oriented_segments;
using detail::prune_stubs;
using detail::split_self_loops;

// Clean-up, orientation and HCLM segments (see the header).
NetworkBuild finish(Graph& g, NetworkStats stats, const Orient& orient) {
  NetworkBuild out;
  if (orient.sac_mm && !orient.inlet_mm) {
    out.error = kSacNeedsInlet;
    return out;
  }
  merge_collapsed(g);
  prune_stubs(g, stats);
  contract_short_branches(g, stats);
  split_self_loops(g);
  join_chains(g, stats);
  std::size_t inlet = kNone;
  double inlet_gap = 0.0;
  if (orient.inlet_mm) {
    inlet = nearest_free_end(g, *orient.inlet_mm, inlet_gap);
    if (inlet == kNone) {
      out.error = "--inlet: the network has no free end to be the inlet";
      return out;
    }
  }
  if (!oriented_segments(g, inlet, out, stats)) return out;
  if (out.model.segments.empty()) out.error = "no vessel left: every polyline was a single point";
  out.stats = stats;
  if (out.ok() && orient.inlet_mm) out.oriented = inlet_note(out.model, *orient.inlet_mm, inlet_gap);
  if (out.ok() && orient.sac_mm) name_sac(out, *orient.sac_mm);
  return out;
}

}  // namespace

NetworkBuild build_network(const std::vector<Polyline>& polylines, const Orient& orient) {
  Graph g;
  NetworkStats stats;
  stats.polylines = polylines.size();
  for (const Polyline& line : polylines) {
    const auto& p = line.points;
    if (p.size() < 2) continue;
    const auto on_network = [&](std::size_t i) {
      if (g.edges().empty()) return false;
      return g.nearest(p[i].pos_mm).distance <= kOverlapRadii * p[i].radius_mm;
    };
    const std::size_t n = p.size();
    std::size_t lead = 0;  // points at the start lying on the network
    while (lead < n && on_network(lead)) ++lead;
    if (lead == n) {
      ++stats.duplicates;
      stats.shared_points += n;
      continue;
    }
    std::size_t trail = 0;  // ... and at the end
    while (trail < n - lead && on_network(n - 1 - trail)) ++trail;
    if (lead > 1 || trail > 1) ++stats.overlapping;
    stats.shared_points += (lead > 1 ? lead - 1 : 0) + (trail > 1 ? trail - 1 : 0);
    // The new branch: from the last shared point's place on the network (or a new free end) to
    // the first shared point's place at the end (or a new free end).
    std::vector<CenterlinePoint> points;
    std::size_t from = kNone;
    if (lead > 0) {
      const Location at = g.nearest(p[lead - 1].pos_mm);
      from = g.attach(at, p[lead - 1].radius_mm);
      points.push_back({g.node(from), p[lead].radius_mm});  // with the branch's own radius
    } else {
      from = g.add_node(p[0].pos_mm);
      points.push_back(p[0]);
    }
    const std::size_t last_new = trail > 0 ? n - trail : n;  // one past the last point of our own
    for (std::size_t i = lead == 0 ? 1 : lead; i < last_new; ++i) points.push_back(p[i]);
    std::size_t to = kNone;
    if (trail > 0) {
      const Location at = g.nearest(p[n - trail].pos_mm);
      to = g.attach(at, p[n - trail].radius_mm);
      points.push_back({g.node(to), p[n - trail - 1].radius_mm});
    } else if (glm::length(points.back().pos_mm - g.node(from)) <= kOverlapRadii * points.back().radius_mm) {
      to = from;  // a closed curve: back to its own start
    } else {
      to = g.add_node(points.back().pos_mm);
    }
    if (points.size() < 2 || (from == to && points.size() < 3)) continue;
    g.add_edge(std::move(points), from, to, line.name);
  }
  join_near_ends(g, stats);
  return finish(g, stats, orient);
}

NetworkBuild build_network(const std::vector<Branch>& branches, const Orient& orient) {
  Graph g;
  NetworkStats stats;
  stats.polylines = branches.size();
  std::map<std::size_t, std::size_t> node_of;  // given id -> graph node
  const auto node = [&](std::size_t id, const glm::dvec3& p) {
    const auto [it, inserted] = node_of.try_emplace(id, 0);
    if (inserted) it->second = g.add_node(p);
    return it->second;
  };
  for (const Branch& branch : branches) {
    if (branch.line.points.size() < 2) continue;
    const std::size_t a = node(branch.from, branch.line.points.front().pos_mm);
    const std::size_t b = node(branch.to, branch.line.points.back().pos_mm);
    g.add_edge(branch.line.points, a, b, branch.line.name);
  }
  return finish(g, stats, orient);
}

}  // namespace cathbox::vessel_import
