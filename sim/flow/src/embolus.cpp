#include "flow/embolus.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "lumen.hpp"

namespace cathbox::flow {
namespace {

constexpr std::size_t kMaxMoves = 100000;  // a path never revisits a segment in a solved network
constexpr double kSameArc_mm = 1e-9;

// The flow segment `f` takes away from `node` (negative: into it; 0: not at it).
double away_from(const SegmentFlow& f, int node) {
  return f.start_node == node ? f.flow_mm3_s : (f.end_node == node ? -f.flow_mm3_s : 0.0);
}

// The segment taking the most flow away from `node` (other than `from`), or -1 (an outlet).
int next_branch(const std::vector<SegmentFlow>& flows, std::uint32_t from, int node, double noise) {
  double best = noise;
  int next = -1;
  for (std::size_t j = 0; j < flows.size(); ++j) {
    if (j == from) continue;
    const double away = away_from(flows[j], node);
    if (away > best) {
      best = away;
      next = static_cast<int>(j);
    }
  }
  return next;
}

// Whether the aspiration sinks at `node` draw more than any segment (but `from`) takes away.
bool sink_outdraws(const FlowNetwork& network, std::uint32_t from, int node, double noise) {
  const double sink = network.sink_flow_at_mm3_s(node);
  if (!(sink > noise)) return false;
  const int next = next_branch(network.segments(), from, node, noise);
  return next < 0 || sink > away_from(network.segments()[static_cast<std::size_t>(next)], node);
}

// The noise floor of the network's flows: below it a segment carries nothing.
double flow_noise(const FlowNetwork& network) {
  double max_flow = 0.0;
  for (const SegmentFlow& s : network.segments()) max_flow = std::max(max_flow, std::abs(s.flow_mm3_s));
  return 1e-9 * max_flow;
}

// The fragment as a clot ending (in its direction of travel) at arc `at_mm` of a segment
// `length_mm` long.
Clot clot_ending_at(std::uint32_t seg, double at_mm, double length_mm, bool forward, const Fragment& f) {
  const double start = forward ? std::max(0.0, at_mm - f.length_mm) : at_mm;
  const double end = forward ? at_mm : std::min(length_mm, at_mm + f.length_mm);
  Clot c{seg, start, std::max(end - start, 1e-3), f.composition, 0.0};
  c.arc_start_mm = std::min(c.arc_start_mm, length_mm - c.length_mm);
  return c;
}

// The distance x along a truncated cone (radius r0 at 0, r1 at `length_mm`) holding the lumen
// volume `volume_mm3`: pi (r0^2 x + r0 k x^2 + k^2 x^3 / 3) = V, k = (r1 - r0) / L, by Newton
// from the linear guess (the volume is increasing and its slope pi r^2 > 0).
double cone_distance_mm(double r0, double r1, double length_mm, double volume_mm3) {
  const double k = (r1 - r0) / length_mm;
  double x = length_mm * volume_mm3 / cone_volume_mm3(r0, r1, length_mm);
  for (int it = 0; it < 8; ++it) {
    const double r = r0 + k * x;
    const double f = std::numbers::pi * (r0 * r0 * x + r0 * k * x * x + k * k * x * x * x / 3.0) - volume_mm3;
    const double dx = f / (std::numbers::pi * r * r);
    x = std::clamp(x - dx, 0.0, length_mm);
    if (std::abs(dx) < 1e-12 * length_mm) break;
  }
  return x;
}

}  // namespace

base::Result<EmbolusTransit> EmbolusTransit::start(const FlowNetwork& network, const Fragment& f) {
  const vessel::VesselModel& model = network.model();
  if (f.from.segment >= model.segments.size()) return base::Error{"embolus: no segment index " + std::to_string(f.from.segment)};
  if (!(std::isfinite(f.diameter_mm) && f.diameter_mm > 0.0 && std::isfinite(f.length_mm) && f.length_mm > 0.0)) {
    return base::Error{"embolus: diameter and length must be > 0"};
  }
  if (const char* e = check_composition(f.composition); *e != '\0') return base::Error{std::string("embolus: ") + e};
  EmbolusTransit t;
  t.fragment_ = f;
  t.enter(network, f.from.segment, f.from.arc_mm);
  if (!t.done()) t.aspirate_at_start(network);
  return t;
}

// Released at a segment's end (a node) where an aspiration sink draws more than any segment
// takes away: straight into the catheter.
void EmbolusTransit::aspirate_at_start(const FlowNetwork& network) {
  const SegmentFlow& s = network.segments()[seg_];
  const int node = arc_mm_ <= kSameArc_mm ? s.start_node : (arc_mm_ >= arcs_.back() - kSameArc_mm ? s.end_node : -1);
  if (node < 0) return;
  if (sink_outdraws(network, std::numeric_limits<std::uint32_t>::max(), node, flow_noise(network))) {
    path_.aspirated = true;
    state_ = TransitState::kAspirated;
  }
}

// Into `segment` at `arc_mm` (clamped to it): a point right there narrower than the fragment
// stops it at once.
void EmbolusTransit::enter(const FlowNetwork& network, std::uint32_t segment, double arc_mm) {
  const vessel::Segment& s = network.model().segments[segment];
  seg_ = segment;
  arcs_ = point_arcs_mm(s);
  arc_mm_ = std::clamp(arc_mm, 0.0, arcs_.back());
  path_.segments.push_back(segment);
  const double q = network.segments()[segment].flow_mm3_s;
  for (std::size_t i = 0; i < arcs_.size(); ++i) {
    if (q == 0.0 || std::abs(arcs_[i] - arc_mm_) > kSameArc_mm || 2.0 * s.points[i].radius_mm >= fragment_.diameter_mm) continue;
    path_.lodged = clot_ending_at(segment, arcs_[i], arcs_.back(), q > 0.0, fragment_);
    state_ = TransitState::kLodged;
    return;
  }
}

double EmbolusTransit::move(const FlowNetwork& network, double budget_s, double noise) {
  const std::vector<SegmentFlow>& flows = network.segments();
  const vessel::Segment& s = network.model().segments[seg_];
  const double q = flows[seg_].flow_mm3_s;
  if (std::abs(q) <= noise) {
    state_ = TransitState::kStalled;
    return budget_s;
  }
  state_ = TransitState::kTravelling;
  const bool forward = q > 0.0;
  // The next centreline point ahead.
  const auto ahead = forward ? std::upper_bound(arcs_.begin(), arcs_.end(), arc_mm_ + kSameArc_mm)
                             : std::lower_bound(arcs_.begin(), arcs_.end(), arc_mm_ - kSameArc_mm);
  if (forward ? ahead == arcs_.end() : ahead == arcs_.begin()) {  // at the segment's end: a junction or an outlet
    const int node = forward ? flows[seg_].end_node : flows[seg_].start_node;
    if (sink_outdraws(network, seg_, node, noise)) {
      path_.aspirated = true;
      state_ = TransitState::kAspirated;
      return 0.0;
    }
    const int next = next_branch(flows, seg_, node, noise);
    if (next < 0) {  // an outlet: it lodges at the end of the model, in that territory
      const double len = std::min(fragment_.length_mm, arcs_.back());
      path_.lodged = Clot{seg_, forward ? arcs_.back() - len : 0.0, len, fragment_.composition, 0.0};
      path_.at_outlet = true;
      state_ = TransitState::kAtOutlet;
      return 0.0;
    }
    const auto n = static_cast<std::size_t>(next);
    enter(network, static_cast<std::uint32_t>(n), flows[n].start_node == node ? 0.0 : std::numeric_limits<double>::infinity());
    return 0.0;
  }
  const auto i = static_cast<std::size_t>(forward ? ahead - arcs_.begin() : ahead - arcs_.begin() - 1);
  const double step_mm = std::abs(arcs_[i] - arc_mm_);
  const double r_here = radius_at_mm(s, arcs_, arc_mm_);
  const double need_s = cone_volume_mm3(r_here, s.points[i].radius_mm, step_mm) / std::abs(q);
  if (need_s > budget_s) {  // part of the way: as far as the flow of `budget_s` fills
    const double part_mm = cone_distance_mm(r_here, s.points[i].radius_mm, step_mm, budget_s * std::abs(q));
    arc_mm_ += forward ? part_mm : -part_mm;
    travelled_mm_ += part_mm;
    return budget_s;
  }
  arc_mm_ = arcs_[i];
  travelled_mm_ += step_mm;
  if (2.0 * s.points[i].radius_mm < fragment_.diameter_mm) {
    path_.lodged = clot_ending_at(seg_, arcs_[i], arcs_.back(), forward, fragment_);
    state_ = TransitState::kLodged;
  }
  return need_s;
}

TransitState EmbolusTransit::advance(const FlowNetwork& network, double dt_s) {
  if (done()) return state_;
  const double noise = flow_noise(network);
  double remaining = dt_s;
  for (std::size_t k = 0; k < kMaxMoves && remaining > 0.0 && !done(); ++k) {
    const double used = move(network, remaining, noise);
    if (state_ == TransitState::kStalled) {
      if (std::isfinite(remaining)) elapsed_s_ += remaining;
      break;
    }
    remaining -= used;
    elapsed_s_ += used;
  }
  return state_;
}

base::Result<EmbolusPath> carry_fragment(const FlowNetwork& network, const Fragment& f) {
  base::Result<EmbolusTransit> t = EmbolusTransit::start(network, f);
  if (!t) return t.error();
  t->advance(network, std::numeric_limits<double>::infinity());
  if (t->state() == TransitState::kStalled) {
    return base::Error{"embolus: no flow carries it in segment " + std::to_string(network.model().segments[t->position().segment].id)};
  }
  if (!t->done()) return base::Error{"embolus: its path does not end"};
  if (t->state() == TransitState::kAspirated) return base::Error{"embolus: an aspiration catheter draws it in"};
  return t->path();
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
