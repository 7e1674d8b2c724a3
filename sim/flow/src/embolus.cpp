#include "flow/embolus.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "lumen.hpp"

namespace cathbox::flow {
namespace {

constexpr std::size_t kMaxHops = 10000;  // a path never revisits a segment in a solved network

// The fragment as a clot at the first centreline point downstream of `arc` narrower than it,
// travelling forward (first to last point) or backward; none when it fits all the way.
std::optional<Clot> lodging(const vessel::Segment& s, std::uint32_t seg, double arc, bool forward, const Fragment& f) {
  const std::vector<double> arcs = point_arcs_mm(s);
  const double length = arcs.back();
  const std::size_t n = arcs.size();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = forward ? k : n - 1 - k;
    const bool downstream = forward ? arcs[i] >= arc : arcs[i] <= arc;
    if (!downstream || 2.0 * s.points[i].radius_mm >= f.diameter_mm) continue;
    const double start = forward ? std::max(0.0, arcs[i] - f.length_mm) : arcs[i];
    const double end = forward ? arcs[i] : std::min(length, arcs[i] + f.length_mm);
    Clot c{seg, start, std::max(end - start, 1e-3), f.composition, 0.0};
    c.arc_start_mm = std::min(c.arc_start_mm, length - c.length_mm);
    return c;
  }
  return std::nullopt;
}

// The segment taking the most flow away from `node` (other than `from`), or -1 (an outlet).
int next_branch(const std::vector<SegmentFlow>& flows, std::uint32_t from, int node, double noise) {
  double best = noise;
  int next = -1;
  for (std::size_t j = 0; j < flows.size(); ++j) {
    if (j == from) continue;
    const double away = flows[j].start_node == node ? flows[j].flow_mm3_s : (flows[j].end_node == node ? -flows[j].flow_mm3_s : 0.0);
    if (away > best) {
      best = away;
      next = static_cast<int>(j);
    }
  }
  return next;
}

}  // namespace

base::Result<EmbolusPath> carry_fragment(const FlowNetwork& network, const Fragment& f) {
  const vessel::VesselModel& model = network.model();
  const std::vector<SegmentFlow>& flows = network.segments();
  if (f.from.segment >= model.segments.size()) return base::Error{"embolus: no segment index " + std::to_string(f.from.segment)};
  if (!(std::isfinite(f.diameter_mm) && f.diameter_mm > 0.0 && std::isfinite(f.length_mm) && f.length_mm > 0.0)) {
    return base::Error{"embolus: diameter and length must be > 0"};
  }
  if (const char* e = check_composition(f.composition); *e != '\0') return base::Error{std::string("embolus: ") + e};
  double max_flow = 0.0;
  for (const SegmentFlow& s : flows) max_flow = std::max(max_flow, std::abs(s.flow_mm3_s));
  const double noise = 1e-9 * max_flow;

  EmbolusPath path;
  std::uint32_t seg = f.from.segment;
  double arc = f.from.arc_mm;
  for (std::size_t hop = 0; hop < kMaxHops; ++hop) {
    const double q = flows[seg].flow_mm3_s;
    if (std::abs(q) <= noise) return base::Error{"embolus: no flow carries it in segment " + std::to_string(model.segments[seg].id)};
    path.segments.push_back(seg);
    const bool forward = q > 0.0;
    if (std::optional<Clot> c = lodging(model.segments[seg], seg, arc, forward, f)) {
      path.lodged = *c;
      return path;
    }
    const int node = forward ? flows[seg].end_node : flows[seg].start_node;
    const int next = next_branch(flows, seg, node, noise);
    if (next < 0) {  // an outlet: it lodges at the end of the model, in that territory
      const double length = point_arcs_mm(model.segments[seg]).back();
      const double len = std::min(f.length_mm, length);
      path.lodged = Clot{seg, forward ? length - len : 0.0, len, f.composition, 0.0};
      path.at_outlet = true;
      return path;
    }
    seg = static_cast<std::uint32_t>(next);
    arc = flows[seg].start_node == node ? 0.0 : point_arcs_mm(model.segments[seg]).back();
  }
  return base::Error{"embolus: its path does not end"};
}

std::vector<std::size_t> new_territories(const TargetTerritory& target, const std::vector<Terminal>& without,
                                         const std::vector<Terminal>& with_embolus) {
  std::vector<std::size_t> starved;
  for (std::size_t k = 0; k < without.size() && k < with_embolus.size(); ++k) {
    if (without[k].role != EndRole::kOutlet || !(without[k].flow_ml_min > 0.0)) continue;
    const bool in_target = std::any_of(target.outlets().begin(), target.outlets().end(), [&](const TerritoryOutlet& o) { return o.terminal == k; });
    if (in_target) continue;
    if (without[k].flow_ml_min - with_embolus[k].flow_ml_min > kHypoperfusedDrop * without[k].flow_ml_min) starved.push_back(k);
  }
  return starved;
}

}  // namespace cathbox::flow
