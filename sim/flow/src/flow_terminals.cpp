// FlowNetwork's terminals: each free end's role (inlet, outlet, closed sac), its outlet target
// (territories, Murray's law) and inflow, from the defaults and the case's settings.
#include "flow_terminals.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>

namespace cathbox::flow::terminals {
namespace {

std::string located_error(const FlowSettings& s, std::size_t line, const std::string& message) {
  if (s.source.empty()) return "flow: " + message;
  return s.source + ":" + std::to_string(line) + ": " + message;
}

double end_radius(const vessel::Segment& s, bool at_end) {
  return (at_end ? s.points.back() : s.points.front()).radius_mm;
}

double cube(double r) { return r * r * r; }

// The terminal a case setting names (a segment id and which end), or one located line.
base::Result<std::size_t> find_setting_terminal(const vessel::VesselModel& model, const FlowSettings& set,
                                                const std::vector<Terminal>& terminals, const SegmentSetting& o, bool at_end,
                                                const char* what) {
  const std::optional<std::size_t> idx = model.index_of(o.segment_id);
  if (!idx) return base::Error{located_error(set, o.line, std::string(what) + ": no segment " + std::to_string(o.segment_id) + " in the vessel model")};
  for (std::size_t k = 0; k < terminals.size(); ++k) {
    if (terminals[k].segment == *idx && terminals[k].at_end == at_end) return k;
  }
  return base::Error{located_error(set, o.line, std::string(what) + ": segment " + std::to_string(o.segment_id) + "'s " +
                                                    (at_end ? "distal" : "proximal") + " end is not a free end")};
}

using TerritoryGroups = std::map<std::pair<Territory, Side>, double>;

// Sum of r^3 over the open, default outlets of each (territory, side).
TerritoryGroups territory_r3(const vessel::VesselModel& model, const std::vector<Terminal>& terminals, const std::vector<std::size_t>& ks) {
  TerritoryGroups group_r3;
  for (std::size_t k : ks) {
    const Terminal& t = terminals[k];
    if (t.role != EndRole::kOutlet || t.overridden || t.territory == Territory::kNone) continue;
    const double r = end_radius(model.segments[t.segment], t.at_end);
    group_r3[{t.territory, side_of(model.segments[t.segment].name)}] += cube(r);
  }
  return group_r3;
}

}  // namespace

// Terminals by name: free starts are inlets, free ends outlets, blind sacs closed.
std::vector<Terminal> default_terminals(const vessel::VesselModel& model, const vessel::VesselGraph& graph, const EndNodes& nodes,
                                        const FlowSettings& set) {
  std::vector<Terminal> terminals;
  for (const vessel::SegmentEnd& e : graph.free_ends()) {
    Terminal t;
    t.segment = e.segment;
    t.at_end = e.at_end;
    t.node = nodes.node(e.segment, e.at_end);
    const vessel::Segment& s = model.segments[e.segment];
    if (!e.at_end) {
      t.role = EndRole::kInlet;
    } else if (is_sac_name(s.name)) {
      t.role = EndRole::kClosed;
      t.target_ml_min = set.sac_exchange_fraction;
    } else {
      t.role = EndRole::kOutlet;
      t.territory = territory_of(s.name);
    }
    terminals.push_back(t);
  }
  return terminals;
}

// The case's closed ends, outlet targets and inflows override the defaults.
base::Status<> apply_case_terminals(const vessel::VesselModel& model, const FlowSettings& set, std::vector<Terminal>& terminals) {
  for (const SegmentSetting& o : set.closed) {
    const base::Result<std::size_t> k = find_setting_terminal(model, set, terminals, o, true, "flow closed");
    if (!k) return k.error();
    Terminal& t = terminals[*k];
    t.role = EndRole::kClosed;
    t.target_ml_min = o.value;
    t.overridden = true;
  }
  for (const SegmentSetting& o : set.outlets) {
    const base::Result<std::size_t> k = find_setting_terminal(model, set, terminals, o, true, "flow outlet");
    if (!k) return k.error();
    Terminal& t = terminals[*k];
    if (t.role == EndRole::kClosed && t.overridden) {
      return base::Error{located_error(set, o.line, "flow outlet: segment " + std::to_string(o.segment_id) + " is also given as closed")};
    }
    t.role = EndRole::kOutlet;
    t.territory = territory_of(model.segments[t.segment].name);
    t.target_ml_min = o.value;
    t.overridden = true;
  }
  for (const SegmentSetting& o : set.inflows) {
    const base::Result<std::size_t> k = find_setting_terminal(model, set, terminals, o, false, "flow inflow");
    if (!k) return k.error();
    terminals[*k].target_ml_min = o.value;
    terminals[*k].overridden = true;
  }
  return base::Ok{};
}

// A component without an inlet takes its widest open free end as one.
void promote_widest_outlet(const vessel::VesselModel& model, std::vector<Terminal>& terminals, const std::vector<std::size_t>& ks) {
  const auto role_count = [&](EndRole r) {
    return std::count_if(ks.begin(), ks.end(), [&](std::size_t k) { return terminals[k].role == r; });
  };
  if (role_count(EndRole::kInlet) > 0 || role_count(EndRole::kOutlet) < 2) return;
  std::size_t widest = ks.front();
  double r_max = -1.0;
  for (std::size_t k : ks) {
    const Terminal& t = terminals[k];
    if (t.role != EndRole::kOutlet || t.overridden) continue;
    const double r = end_radius(model.segments[t.segment], t.at_end);
    if (r > r_max) {
      r_max = r;
      widest = k;
    }
  }
  if (r_max > 0.0) {
    terminals[widest].role = EndRole::kInlet;
    terminals[widest].territory = Territory::kNone;
  }
}

// Outlet targets: overrides; territories (a side's share split among its outlets by r^3);
// the descending aorta takes the rest of the cardiac output; Murray's law otherwise.
void assign_outlet_targets(const vessel::VesselModel& model, const FlowSettings& set, std::vector<Terminal>& terminals,
                           const std::vector<std::size_t>& ks) {
  TerritoryGroups group_r3 = territory_r3(model, terminals, ks);
  double assigned = 0.0;
  for (std::size_t k : ks) {
    Terminal& t = terminals[k];
    if (t.role != EndRole::kOutlet) continue;
    const vessel::Segment& s = model.segments[t.segment];
    const double r = end_radius(s, t.at_end);
    if (!t.overridden) {
      if (t.territory == Territory::kNone) {
        t.target_ml_min = murray_flow_ml_min(r, set);
      } else if (t.territory != Territory::kDescendingAorta) {
        const Side side = side_of(s.name);
        const double total = territory_flow_per_side_ml_min(t.territory, set) * (side == Side::kNone ? 2.0 : 1.0);
        t.target_ml_min = total * r * r * r / group_r3[{t.territory, side}];
      }
    }
    if (t.overridden || t.territory != Territory::kDescendingAorta) assigned += t.target_ml_min;
  }
  const double rest = set.cardiac_output_ml_min - assigned;
  double desc_total = 0.0;
  for (const auto& [key, r3] : group_r3) {
    if (key.first == Territory::kDescendingAorta) desc_total += r3;
  }
  for (std::size_t k : ks) {
    Terminal& t = terminals[k];
    if (t.role != EndRole::kOutlet || t.overridden || t.territory != Territory::kDescendingAorta) continue;
    const double r = end_radius(model.segments[t.segment], t.at_end);
    t.target_ml_min = rest > 0.0 ? rest * r * r * r / desc_total : murray_flow_ml_min(r, set);
  }
}

// Inflows: prescribed ones, the rest of the outlets' total shared by r^3.
void assign_inflows(const vessel::VesselModel& model, std::vector<Terminal>& terminals, const std::vector<std::size_t>& ks) {
  double outflow = 0.0, fixed = 0.0, free_r3 = 0.0;
  for (std::size_t k : ks) {
    const Terminal& t = terminals[k];
    const double r = end_radius(model.segments[t.segment], t.at_end);
    if (t.role == EndRole::kOutlet) outflow += t.target_ml_min;
    if (t.role == EndRole::kInlet && t.overridden) fixed += t.target_ml_min;
    if (t.role == EndRole::kInlet && !t.overridden) free_r3 += r * r * r;
  }
  for (std::size_t k : ks) {
    Terminal& t = terminals[k];
    if (t.role != EndRole::kInlet || t.overridden) continue;
    const double r = end_radius(model.segments[t.segment], t.at_end);
    t.target_ml_min = std::max(0.0, outflow - fixed) * r * r * r / free_r3;
  }
}

}  // namespace cathbox::flow::terminals
