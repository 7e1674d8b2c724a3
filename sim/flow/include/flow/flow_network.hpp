#pragma once
// Steady blood flow over a vessel network as a resistor network (the hydraulic analogue of
// Ohm's and Kirchhoff's laws).
//
// - Every segment is a Poiseuille resistor: R = integral of 8 mu / (pi r^4) along its centreline,
//   exact for the truncated cones between centreline points:
//   8 mu L (r0^2 + r0 r1 + r1^2) / (3 pi r0^3 r1^3).
// - Nodes are the graph's junctions and free ends (vessel::VesselGraph). A free segment start
//   is an inlet (a root): a prescribed inflow. A free segment end is an outlet: a terminal
//   resistance to the venous pressure, sized from the outlet's target flow Q_target (its
//   territory's share, territory.hpp, or a case override): calibrated (default) so that with the
//   arterial pressure at the inlet every outlet drains its target — R_t = (p_outlet - P_venous) /
//   Q_target from a first solve with the targets as sinks — or fixed, R_t = (P_arterial -
//   P_venous) / Q_target. Either way the network's resistances decide the paths the blood takes
//   (which carotid feeds which territory through the circle of Willis). A blind end (an aneurysm
//   sac, or `flow closed SEG`) is closed: no flow.
// - A root's inflow defaults to the sum of its component's outlet targets (shared among several
//   roots by r^3), so pressures stay near the arterial pressure; a case can prescribe it. A
//   component without a free segment start takes its widest free end as the inlet.
// - Kirchhoff's current law at every node gives a sparse symmetric positive definite system in
//   the node pressures (Eigen's sparse LDL^T), so confluences and loops (circle of Willis) need
//   nothing special. Flows are positive from a segment's first point to its last.
// - Pulsatility (optional): without compliance every flow scales with the inflow, by
//   flow_scale(t).
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "base/result.hpp"
#include "flow/clot.hpp"
#include "flow/flow_settings.hpp"
#include "flow/territory.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::flow {

enum class EndRole : std::uint8_t { kJunction, kInlet, kOutlet, kClosed };

// A free end of the network and what the model does there.
struct Terminal {
  std::uint32_t segment = 0;        // index into the model's segments
  bool at_end = true;               // the segment's last point (else its first)
  EndRole role = EndRole::kOutlet;
  Territory territory = Territory::kNone;  // outlets
  bool overridden = false;          // the target / inflow came from the case
  double target_ml_min = 0.0;       // outlets: target flow; inlets: inflow; closed: exchange fraction
  double resistance_Pa_s_per_mm3 = 0.0;  // outlets: terminal resistance
  double flow_ml_min = 0.0;         // solved flow through the end (into the network for inlets)
  int node = -1;
};

struct SegmentFlow {
  double flow_mm3_s = 0.0;          // signed: positive from the first point to the last
  double length_mm = 0.0;
  double volume_mm3 = 0.0;          // lumen volume (truncated cones)
  double resistance_Pa_s_per_mm3 = 0.0;
  double min_radius_mm = 0.0;
  double mean_velocity_mm_s = 0.0;  // |flow| / (volume / length)
  double peak_velocity_mm_s = 0.0;  // |flow| / (pi r_min^2): cross-section mean at the narrowest point
  double reynolds = 0.0;            // rho v d / mu at the mean cross-section, rho = 1060 kg/m^3
  int start_node = -1;
  int end_node = -1;
  [[nodiscard]] double flow_ml_min() const { return flow_mm3_s * 0.06; }
};

// An aspiration catheter's open tip drawing blood out of the network: a sink at the node
// nearest the tip (the nearer end of the segment it is in), through the catheter's lumen (a
// Poiseuille resistance over its length and inner diameter: catheter_resistance_Pa_s_per_mm3)
// to the pump's vacuum. The sink's flow is (p_node - p_vacuum) / R, p_vacuum the gauge vacuum
// below the venous pressure the network's pressures are measured from.
struct AspirationSink {
  std::uint32_t segment = 0;  // where the tip is (index into the model's segments)
  double arc_mm = 0.0;        // along it
  double vacuum_Pa = 0.0;     // gauge, negative (flow::vacuum_Pa: -86.8 kPa for the pump)
  double resistance_Pa_s_per_mm3 = 0.0;  // the catheter's lumen
};

// Poiseuille's resistance of a catheter's lumen, 128 mu L / (pi ID^4), Pa s / mm^3.
[[nodiscard]] double catheter_resistance_Pa_s_per_mm3(double length_mm, double inner_diameter_mm, double viscosity_mPa_s);

class FlowNetwork;

// The solved network, or one line ("file:line: message" for a case override).
using FlowBuild = base::Result<std::unique_ptr<FlowNetwork>>;

class FlowNetwork {
 public:
  // Builds and solves. The model must have passed validation (vessel::validate_model).
  [[nodiscard]] static FlowBuild build(const vessel::VesselModel& model, const FlowSettings& settings = {});

  [[nodiscard]] const vessel::VesselModel& model() const { return model_; }
  [[nodiscard]] const FlowSettings& settings() const { return settings_; }
  [[nodiscard]] const std::vector<SegmentFlow>& segments() const { return segments_; }
  [[nodiscard]] const std::vector<Terminal>& terminals() const { return terminals_; }
  [[nodiscard]] std::size_t node_count() const { return pressure_Pa_.size(); }
  // Pressure above the venous pressure at a node, Pa; absolute in mmHg.
  [[nodiscard]] double node_pressure_Pa(int node) const { return pressure_Pa_[static_cast<std::size_t>(node)]; }
  [[nodiscard]] double node_pressure_mmHg(int node) const;
  [[nodiscard]] double total_inflow_ml_min() const;
  // The index in terminals() of the closed end of segment `segment`, or -1.
  [[nodiscard]] int closed_terminal_of(std::uint32_t segment) const;

  // Occludes the network with these clots (replacing any earlier ones; none restores the open
  // network) and solves again with the terminal resistances of the open network: the
  // territories downstream of a clot lose their flow, which goes where the network's other
  // paths take it (collaterals). An error (nothing changed) for a clot outside its segment,
  // a bad composition or open fraction. Balloons (`arrests`) seal their segments: flow arrest.
  // Aspiration catheters' open tips (`sinks`) draw blood at their nodes; the inflows stay as
  // prescribed, so what the sinks take the outlets lose.
  [[nodiscard]] base::Status<> occlude(std::span<const Clot> clots, std::span<const FlowArrest> arrests = {},
                                       std::span<const AspirationSink> sinks = {});
  [[nodiscard]] const std::vector<Clot>& clots() const { return clots_; }
  [[nodiscard]] const std::vector<FlowArrest>& arrests() const { return arrests_; }
  [[nodiscard]] const std::vector<AspirationSink>& sinks() const { return sinks_; }
  // Sink k's node and the flow it draws out of the network there, mL/min (> 0: into the catheter).
  [[nodiscard]] int sink_node(std::size_t k) const { return sink_nodes_[k]; }
  [[nodiscard]] double sink_flow_ml_min(std::size_t k) const;
  // The node an aspiration sink at `arc_mm` of `segment` draws at: the segment's nearer end.
  [[nodiscard]] int nearer_node(std::uint32_t segment, double arc_mm) const;
  // The flow the sinks at `node` draw, mm^3/s (0 for none).
  [[nodiscard]] double sink_flow_at_mm3_s(int node) const;

  // Pulsatility factor of every flow at time t (1 for steady flow), and its maximum.
  [[nodiscard]] double flow_scale(double time_s) const;
  [[nodiscard]] double max_flow_scale() const;

 private:
  FlowNetwork() = default;
  base::Status<> solve();
  base::Status<> solve_pressures();
  // A sink's vacuum as the network measures pressure (above venous), Pa.
  [[nodiscard]] double sink_pressure_Pa(const AspirationSink& s) const;

  vessel::VesselModel model_;
  FlowSettings settings_;
  std::vector<SegmentFlow> segments_;
  std::vector<Terminal> terminals_;
  std::vector<double> pressure_Pa_;
  std::vector<double> open_resistance_Pa_s_per_mm3_;  // per segment, without clots
  std::vector<Clot> clots_;
  std::vector<FlowArrest> arrests_;
  std::vector<AspirationSink> sinks_;
  std::vector<int> sink_nodes_;
  std::vector<int> idle_pins_;  // a node of each component without outflow, pinned at 0 Pa
};

}  // namespace cathbox::flow
