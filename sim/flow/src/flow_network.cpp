// FlowNetwork: the segments' Poiseuille resistances, the node pressures' sparse solve, the
// terminal resistances calibrated to the targets (the terminals themselves: flow_terminals.cpp).
#include "flow/flow_network.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <tuple>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "lumen.hpp"
#include "vessel/vessel_graph.hpp"

#include "flow_terminals.hpp"

namespace cathbox::flow {
namespace {

using terminals::apply_case_terminals;
using terminals::assign_inflows;
using terminals::assign_outlet_targets;
using terminals::default_terminals;
using terminals::EndNodes;
using terminals::promote_widest_outlet;

constexpr double kBloodDensity_kg_m3 = 1060.0;

class NodeSets {
 public:
  explicit NodeSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(std::size_t a, std::size_t b) { parent_[find(a)] = find(b); }

 private:
  std::vector<std::size_t> parent_;
};

std::string check_settings(const FlowSettings& s) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(s.viscosity_mPa_s)) return "flow: viscosity must be > 0";
  if (!positive(s.cardiac_output_ml_min)) return "flow: cardiac output must be > 0";
  if (!(s.cerebral_fraction > 0.0 && s.cerebral_fraction < 1.0)) return "flow: cerebral fraction must be in (0, 1)";
  if (!(std::isfinite(s.arterial_pressure_mmHg) && std::isfinite(s.venous_pressure_mmHg) &&
        s.arterial_pressure_mmHg > s.venous_pressure_mmHg)) {
    return "flow: arterial pressure must be finite and above the venous pressure";
  }
  if (!positive(s.wall_shear_stress_Pa)) return "flow: wall shear stress must be > 0";
  if (!(std::isfinite(s.dispersion_radii) && s.dispersion_radii >= 0.0)) return "flow: dispersion must be >= 0";
  if (!(std::isfinite(s.sac_exchange_fraction) && s.sac_exchange_fraction >= 0.0 && s.sac_exchange_fraction <= 1.0)) {
    return "flow: sac exchange fraction must be in [0, 1]";
  }
  if (!(std::isfinite(s.heart_rate_bpm) && s.heart_rate_bpm >= 0.0 && s.heart_rate_bpm <= 300.0)) {
    return "flow: heart rate must be in [0, 300] bpm";
  }
  if (!(std::isfinite(s.pulsatility_index) && s.pulsatility_index >= 0.0 && s.pulsatility_index <= 2.0)) {
    return "flow: pulsatility index must be in [0, 2]";
  }
  return {};
}

// Segment geometry and resistance (Poiseuille over truncated cones).
std::vector<SegmentFlow> measure_segments(const vessel::VesselModel& model, const EndNodes& nodes, double mu) {
  std::vector<SegmentFlow> segments(model.segments.size());
  for (std::size_t i = 0; i < model.segments.size(); ++i) {
    const vessel::Segment& s = model.segments[i];
    SegmentFlow& f = segments[i];
    f.min_radius_mm = s.points.front().radius_mm;
    for (std::size_t p = 1; p < s.points.size(); ++p) {
      const double r0 = s.points[p - 1].radius_mm;
      const double r1 = s.points[p].radius_mm;
      const double len = glm::length(s.points[p].pos_mm - s.points[p - 1].pos_mm);
      f.length_mm += len;
      f.volume_mm3 += cone_volume_mm3(r0, r1, len);
      f.resistance_Pa_s_per_mm3 += cone_resistance(r0, r1, len, mu);
      f.min_radius_mm = std::min(f.min_radius_mm, r1);
    }
    f.resistance_Pa_s_per_mm3 = std::max(f.resistance_Pa_s_per_mm3, kMinResistance);
    f.start_node = nodes.node(i, false);
    f.end_node = nodes.node(i, true);
  }
  return segments;
}

// The connected component (its representative node) of every node.
std::vector<std::size_t> node_components(const std::vector<SegmentFlow>& segments, std::size_t n_nodes) {
  NodeSets sets(n_nodes);
  for (const SegmentFlow& f : segments) sets.unite(static_cast<std::size_t>(f.start_node), static_cast<std::size_t>(f.end_node));
  std::vector<std::size_t> component(n_nodes);
  for (std::size_t v = 0; v < n_nodes; ++v) component[v] = sets.find(v);
  return component;
}

// The segments' conductance Laplacian over the nodes; returns the largest conductance.
double add_segment_laplacian(const std::vector<SegmentFlow>& segments, std::vector<Eigen::Triplet<double>>& triplets) {
  double g_max = 0.0;
  for (const SegmentFlow& f : segments) {
    if (f.start_node == f.end_node) continue;
    const double g = 1.0 / f.resistance_Pa_s_per_mm3;
    g_max = std::max(g_max, g);
    triplets.emplace_back(f.start_node, f.start_node, g);
    triplets.emplace_back(f.end_node, f.end_node, g);
    triplets.emplace_back(f.start_node, f.end_node, -g);
    triplets.emplace_back(f.end_node, f.start_node, -g);
  }
  return g_max;
}

std::optional<Eigen::VectorXd> solve_nodes(std::size_t n_nodes, const std::vector<Eigen::Triplet<double>>& triplets, const Eigen::VectorXd& b) {
  Eigen::SparseMatrix<double> a(static_cast<Eigen::Index>(n_nodes), static_cast<Eigen::Index>(n_nodes));
  a.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  solver.compute(a);
  if (solver.info() != Eigen::Success) return std::nullopt;
  Eigen::VectorXd x = solver.solve(b);
  if (solver.info() != Eigen::Success || !x.allFinite()) return std::nullopt;
  return x;
}

struct ComponentFlows {
  double in_mm3_s = 0.0, out_mm3_s = 0.0;
  int pin = -1;  // an inlet node, held at the arterial pressure when calibrating
  [[nodiscard]] bool flowing() const { return pin >= 0 && in_mm3_s > 0.0 && out_mm3_s > 0.0; }
};
using ComponentMap = std::map<std::size_t, ComponentFlows>;

// Each component's total inflow and outflow targets and its pin; every outlet needs a positive
// target and every inflow an outlet to drain it.
base::Result<ComponentMap> component_flows(const vessel::VesselModel& model, const std::vector<Terminal>& terminals,
                                           const std::vector<std::size_t>& component) {
  ComponentMap comps;
  for (const std::size_t c : component) comps.emplace(c, ComponentFlows{});
  for (const Terminal& t : terminals) {
    ComponentFlows& c = comps[component[static_cast<std::size_t>(t.node)]];
    if (t.role == EndRole::kOutlet) {
      if (!(t.target_ml_min > 0.0) || !std::isfinite(t.target_ml_min)) {
        return base::Error{"flow: outlet of segment " + std::to_string(model.segments[t.segment].id) + " has no positive target flow"};
      }
      c.out_mm3_s += t.target_ml_min / 0.06;
    } else if (t.role == EndRole::kInlet) {
      c.in_mm3_s += t.target_ml_min / 0.06;
      if (c.pin < 0) c.pin = t.node;
    }
  }
  for (const Terminal& t : terminals) {
    if (t.role == EndRole::kInlet && t.target_ml_min > 0.0 && comps[component[static_cast<std::size_t>(t.node)]].out_mm3_s <= 0.0) {
      return base::Error{"flow: segment " + std::to_string(model.segments[t.segment].id) + " has an inflow but its network has no outlet"};
    }
  }
  return comps;
}

struct NodeSystem {
  const std::vector<Eigen::Triplet<double>>& laplacian;
  double g_max = 0.0;
  const std::vector<std::size_t>& component;
};

// Calibrated terminal resistances: with the arterial pressure at the inlet every outlet drains
// its target (the outlets' targets scaled to the inflow): R_t = (p_outlet - P_venous) / Q_target.
base::Status<> calibrate_terminals(const vessel::VesselModel& model, const NodeSystem& sys, const ComponentMap& comps,
                                   double drop_Pa, std::vector<Terminal>& terminals) {
  const std::size_t n_nodes = sys.component.size();
  std::vector<Eigen::Triplet<double>> triplets = sys.laplacian;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n_nodes));
  const double g_pin = sys.g_max > 0.0 ? sys.g_max : 1.0;
  for (const auto& [comp, c] : comps) {
    const int pin = c.flowing() ? c.pin : static_cast<int>(comp);
    triplets.emplace_back(pin, pin, g_pin);
    if (c.flowing()) b[pin] += g_pin * drop_Pa;  // no net flow through the pin: it holds the pressure exactly
  }
  for (const Terminal& t : terminals) {
    const ComponentFlows& c = comps.at(sys.component[static_cast<std::size_t>(t.node)]);
    if (!c.flowing()) continue;
    if (t.role == EndRole::kInlet) b[t.node] += t.target_ml_min / 0.06;
    if (t.role == EndRole::kOutlet) b[t.node] -= t.target_ml_min / 0.06 * c.in_mm3_s / c.out_mm3_s;
  }
  const std::optional<Eigen::VectorXd> pc = solve_nodes(n_nodes, triplets, b);
  if (!pc) return base::Error{"flow: the network's pressure system could not be solved"};
  for (Terminal& t : terminals) {
    const ComponentFlows& c = comps.at(sys.component[static_cast<std::size_t>(t.node)]);
    if (t.role != EndRole::kOutlet || c.pin < 0 || c.in_mm3_s <= 0.0) continue;
    const double p_out = (*pc)[t.node];
    if (!(p_out > 0.0)) {
      return base::Error{"flow: the vessels upstream of segment " + std::to_string(model.segments[t.segment].id) +
                         "'s outlet drop the arterial pressure below the venous pressure at the target flows"};
    }
    t.resistance_Pa_s_per_mm3 = p_out / (t.target_ml_min / 0.06 * c.in_mm3_s / c.out_mm3_s);
  }
  return base::Ok{};
}

}  // namespace

FlowBuild FlowNetwork::build(const vessel::VesselModel& model, const FlowSettings& settings) {
  if (std::string e = check_settings(settings); !e.empty()) return base::Error{std::move(e)};
  for (const vessel::Segment& s : model.segments) {
    if (s.points.size() < 2) return base::Error{"flow: segment " + std::to_string(s.id) + " has fewer than 2 points"};
  }
  std::unique_ptr<FlowNetwork> net(new FlowNetwork());
  net->model_ = model;
  net->settings_ = settings;
  if (base::Status<> solved = net->solve(); !solved) return solved.error();
  return FlowBuild(std::move(net));
}

base::Status<> FlowNetwork::solve() {
  const vessel::VesselModel& model = model_;
  const FlowSettings& set = settings_;
  const vessel::VesselGraph graph(model);
  const EndNodes nodes(graph, model.segments.size());
  segments_ = measure_segments(model, nodes, set.viscosity_mPa_s * 1e-3);
  const std::vector<std::size_t> component = node_components(segments_, nodes.count());

  terminals_ = default_terminals(model, graph, nodes, set);
  if (base::Status<> applied = apply_case_terminals(model, set, terminals_); !applied) return applied;
  std::map<std::size_t, std::vector<std::size_t>> by_component;
  for (std::size_t k = 0; k < terminals_.size(); ++k) by_component[component[static_cast<std::size_t>(terminals_[k].node)]].push_back(k);
  for (const auto& entry : by_component) promote_widest_outlet(model, terminals_, entry.second);
  for (const auto& entry : by_component) {
    assign_outlet_targets(model, set, terminals_, entry.second);
    assign_inflows(model, terminals_, entry.second);
  }

  // Kirchhoff's current law in the node pressures (Pa above venous): the segments' Laplacian
  // plus, per case, terminal conductances to ground and sources.
  const double drop_Pa = (set.arterial_pressure_mmHg - set.venous_pressure_mmHg) * kPa_per_mmHg;
  std::vector<Eigen::Triplet<double>> laplacian;
  laplacian.reserve(4 * segments_.size());
  const double g_max = add_segment_laplacian(segments_, laplacian);
  base::Result<ComponentMap> comps = component_flows(model, terminals_, component);
  if (!comps) return comps.error();
  // Terminal resistances: fixed, R_t = (P_arterial - P_venous) / Q_target; or calibrated.
  for (Terminal& t : terminals_) {
    if (t.role == EndRole::kOutlet) t.resistance_Pa_s_per_mm3 = drop_Pa / (t.target_ml_min / 0.06);
  }
  if (set.calibrate_terminals) {
    const NodeSystem sys{laplacian, g_max, component};
    if (base::Status<> calibrated = calibrate_terminals(model, sys, *comps, drop_Pa, terminals_); !calibrated) return calibrated;
  }
  idle_pins_.clear();
  for (const auto& [comp, c] : *comps) {
    if (c.out_mm3_s <= 0.0) idle_pins_.push_back(static_cast<int>(comp));
  }
  open_resistance_Pa_s_per_mm3_.clear();
  for (const SegmentFlow& f : segments_) open_resistance_Pa_s_per_mm3_.push_back(f.resistance_Pa_s_per_mm3);
  return solve_pressures();
}

// The final solve: the segments' Laplacian (their current resistances, clots included), the
// outlets' terminal conductances to ground and the inlets' inflows.
base::Status<> FlowNetwork::solve_pressures() {
  std::size_t nodes = 0;
  for (const SegmentFlow& f : segments_) nodes = std::max({nodes, static_cast<std::size_t>(f.start_node) + 1, static_cast<std::size_t>(f.end_node) + 1});
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(4 * segments_.size() + terminals_.size() + idle_pins_.size());
  (void)add_segment_laplacian(segments_, triplets);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(nodes));
  for (const Terminal& t : terminals_) {
    if (t.role == EndRole::kOutlet) triplets.emplace_back(t.node, t.node, 1.0 / t.resistance_Pa_s_per_mm3);
    if (t.role == EndRole::kInlet) rhs[t.node] += t.target_ml_min / 0.06;
  }
  for (int pin : idle_pins_) triplets.emplace_back(pin, pin, 1.0);  // no flow: pin
  for (std::size_t k = 0; k < sinks_.size(); ++k) {  // an aspiration catheter to its vacuum
    const double g = 1.0 / sinks_[k].resistance_Pa_s_per_mm3;
    triplets.emplace_back(sink_nodes_[k], sink_nodes_[k], g);
    rhs[sink_nodes_[k]] += g * sink_pressure_Pa(sinks_[k]);
  }
  const std::optional<Eigen::VectorXd> solved = solve_nodes(nodes, triplets, rhs);
  if (!solved) return base::Error{"flow: the network's pressure system could not be solved"};
  const Eigen::VectorXd& p = *solved;
  pressure_Pa_.assign(p.data(), p.data() + p.size());

  const double mu = settings_.viscosity_mPa_s * 1e-3;
  for (SegmentFlow& f : segments_) {
    f.flow_mm3_s = f.start_node == f.end_node ? 0.0 : (p[f.start_node] - p[f.end_node]) / f.resistance_Pa_s_per_mm3;
    const double area = f.length_mm > 0.0 ? f.volume_mm3 / f.length_mm : std::numbers::pi * f.min_radius_mm * f.min_radius_mm;
    f.mean_velocity_mm_s = std::abs(f.flow_mm3_s) / area;
    f.peak_velocity_mm_s = std::abs(f.flow_mm3_s) / (std::numbers::pi * f.min_radius_mm * f.min_radius_mm);
    const double d_mm = 2.0 * std::sqrt(area / std::numbers::pi);
    f.reynolds = kBloodDensity_kg_m3 * f.mean_velocity_mm_s * 1e-3 * d_mm * 1e-3 / mu;
  }
  for (Terminal& t : terminals_) {
    const double q = segments_[t.segment].flow_ml_min();
    const double out = t.at_end ? q : -q;  // out of the network through this end
    t.flow_ml_min = t.role == EndRole::kClosed ? 0.0 : (t.role == EndRole::kInlet ? -out : out);
  }
  return base::Ok{};
}

double FlowNetwork::node_pressure_mmHg(int node) const {
  return settings_.venous_pressure_mmHg + node_pressure_Pa(node) / kPa_per_mmHg;
}

double FlowNetwork::total_inflow_ml_min() const {
  double q = 0.0;
  for (const Terminal& t : terminals_) {
    if (t.role == EndRole::kInlet) q += t.flow_ml_min;
  }
  return q;
}

int FlowNetwork::closed_terminal_of(std::uint32_t segment) const {
  for (std::size_t k = 0; k < terminals_.size(); ++k) {
    if (terminals_[k].segment == segment && terminals_[k].role == EndRole::kClosed) return static_cast<int>(k);
  }
  return -1;
}

double FlowNetwork::flow_scale(double time_s) const {
  if (settings_.heart_rate_bpm <= 0.0 || settings_.pulsatility_index <= 0.0) return 1.0;
  return 1.0 + 0.5 * settings_.pulsatility_index * std::sin(2.0 * std::numbers::pi * time_s * settings_.heart_rate_bpm / 60.0);
}

double FlowNetwork::max_flow_scale() const {
  if (settings_.heart_rate_bpm <= 0.0) return 1.0;
  return 1.0 + 0.5 * settings_.pulsatility_index;
}

}  // namespace cathbox::flow
