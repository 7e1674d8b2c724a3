#include "tool/stent_retriever.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "tool/rod.hpp"

namespace cathbox::tool {
namespace {

// World Neurosurg 2019;121:e358: the clot-capturing ability of the small- (4 mm) and
// large-diameter (6 mm) stents, N.
constexpr double kCapture4mm_N = 0.39;
constexpr double kCapture6mm_N = 0.56;

}  // namespace

double stent_radial_force_N(const StentRetrieverSpec& s, double tube_diameter_mm) {
  if (!(s.diameter_mm > 0.0) || !(tube_diameter_mm < s.diameter_mm)) return 0.0;
  const double oversizing = 1.0 - std::max(tube_diameter_mm, 0.0) / s.diameter_mm;
  return kStentRadialStiffness_N_per_mm * s.length_mm * oversizing;
}

double stent_expanded_diameter_mm(const StentRetrieverSpec& s, double lumen_diameter_mm) {
  return std::min(s.diameter_mm, std::max(lumen_diameter_mm, 0.0));
}

double stent_integration(const StentRetrieverSpec& s, double dwell_s) {
  if (!(dwell_s > 0.0) || !(s.embed_s > 0.0)) return 0.0;
  return 1.0 - std::exp(-kStentIntegrationRate * dwell_s / s.embed_s);
}

double stent_capture_force_N(const StentRetrieverSpec& s) {
  const double per_mm = (kCapture6mm_N - kCapture4mm_N) / 2.0;
  return std::max(0.0, kCapture4mm_N + per_mm * (s.diameter_mm - 4.0));
}

StentRetriever::StentRetriever(const StentRetrieverSpec& spec, std::size_t node_total)
    : spec_(spec),
      gauged_at_(node_total, glm::dvec3(0.0)),
      lumen_mm_(node_total, -1.0),
      expanded_mm_(node_total, 0.0),
      hints_(node_total) {}

// The length of the stent zone [0, L] from the tip that node k stands for: its Voronoi interval
// along the wire (half-way to each neighbour), clamped to the zone.
double StentRetriever::share_mm(const Rod& rod, std::size_t k) const {
  const std::size_t n = rod.node_total();
  const double at = rod.node_from_tip_mm(k);
  const double hi = k > 0 ? 0.5 * (rod.node_from_tip_mm(k - 1) + at) : at;
  const double lo = k + 1 < n ? 0.5 * (at + rod.node_from_tip_mm(k + 1)) : 0.0;
  return std::max(0.0, std::min(hi, spec_.length_mm) - std::max(lo, 0.0));
}

void StentRetriever::update(Rod& rod, const WallModel& wall) {
  const std::size_t n = rod.node_total();
  const std::span<const glm::dvec3> x = rod.positions();
  StentState s;
  s.payload_mN = state_.payload_mN;
  s.first_node = n;
  const bool meshed = wall.surface() != nullptr;  // an analytic wall is its own tubes
  for (std::size_t k = 0; k < n; ++k) {
    const double share = share_mm(rod, k);
    if (share <= 0.0) continue;
    if (k < rod.first_free_node()) {  // crimped in a catheter
      expanded_mm_[k] = 0.0;
      rod.set_grip(k, 0.0);
      rod.set_contact_radius(k, 0.0);
      continue;
    }
    s.first_node = std::min(s.first_node, k);
    if (lumen_mm_[k] < 0.0 || glm::distance(x[k], gauged_at_[k]) > kRegaugeMove_mm) {
      const double r = wall.lumen_radius_mm(x[k]);
      lumen_mm_[k] = r > 0.0 ? 2.0 * r : spec_.diameter_mm;
      gauged_at_[k] = x[k];
    }
    expanded_mm_[k] = stent_expanded_diameter_mm(spec_, lumen_mm_[k]);
    // The expanded stent's contact: the cage fills the lumen, but its axis is not held on the
    // lumen's (its lateral stiffness, k s / D per mm of offset, ~14 mN/mm for a 0.5 mm node of
    // the 4 x 20 mm device, is nothing against the wall's): a tension round a bend or a
    // junction's corner carries the axis off the lumen's, the cage pressed to the inner side,
    // until kStentAxisPlay of the expanded radius. The node's radius against the wall, flaring from the push wire's over kStentFlare_mm past the catheter's tip
    // (the stent funnels into that tip, which need not lie on the lumen's axis), never more
    // than its centre's distance to the nearest wall now plus the play a contact may take (so a
    // node dragged into a narrowing, or next to an off-axis catheter tip, starts no step deep
    // in the wall; one held against the wall keeps its radius).
    // Once its proximal end is at the catheter's tip (no push wire out) the stent is being
    // drawn into the catheter: its cells collapse from that end and it no longer fills the lumen.
    const double out_mm = rod.node_from_tip_mm(rod.first_free_node());
    const double flare = out_mm > spec_.length_mm + kStentClearance_mm ? std::min(1.0, (out_mm - rod.node_from_tip_mm(k)) / kStentFlare_mm) : 0.0;
    // The room binds only when it is below (1 - play) of the fill radius: the wall is looked
    // for that far and no further (a bounded query, which the mesh's coherent hint answers at
    // once for a node clear of it), with the same radius as a search of the whole lumen.
    const double fill_mm = (1.0 - kStentAxisPlay) * 0.5 * expanded_mm_[k];
    WallProbe probe;
    probe.center_mm = x[k];
    probe.range_mm = std::max(0.0, (1.0 - kStentPlay) * fill_mm);
    probe.second_wall = false;
    // The room on both the mesh and the tube round the centreline the node is held by
    // (WallProbe::lumen_axis): the narrower, so that it starts no step deep in either.
    WallContact c;
    double room_mm = wall.probe(probe, hints_[k], c) ? c.distance_mm : fill_mm;
    probe.lumen_axis = true;
    if (meshed && wall.probe(probe, hints_[k], c)) room_mm = std::min(room_mm, c.distance_mm);
    rod.set_contact_radius(k, flare * std::min(fill_mm, room_mm + kStentPlay * fill_mm));
    s.unsheathed_mm += share;
    s.min_diameter_mm = s.min_diameter_mm > 0.0 ? std::min(s.min_diameter_mm, expanded_mm_[k]) : expanded_mm_[k];
    s.max_diameter_mm = std::max(s.max_diameter_mm, expanded_mm_[k]);
  }
  // The radial force per mm of stent in each node's lumen, over its share; the payload by share.
  for (std::size_t k = s.first_node; k < n; ++k) {
    const double share = share_mm(rod, k);
    const double rf_N = stent_radial_force_N(spec_, lumen_mm_[k]) * share / spec_.length_mm;
    s.radial_force_N += rf_N;
    const double payload = s.unsheathed_mm > 0.0 ? s.payload_mN * share / s.unsheathed_mm : 0.0;
    rod.set_grip(k, kStentWallFriction * rf_N * 1000.0 + payload);
  }
  state_ = s;
}

}  // namespace cathbox::tool
