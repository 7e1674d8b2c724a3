// FlowNetwork::occlude: clots and balloons as resistance (flow/clot.hpp), then the final solve again.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "flow/flow_network.hpp"
#include "lumen.hpp"

namespace cathbox::flow {
namespace {

struct ClotResistance {
  double lumen = 0.0;  // the open vessel over the clot's length, Pa.s/mm^3
  double clot = 0.0;   // the clot there: Darcy plug in parallel with the open channel
};

// Resistances over [a, b] of a segment, integrating the truncated cones piece by piece.
ClotResistance clot_resistance(const vessel::Segment& seg, double a, double b, double open_fraction, double mu_Pa_s) {
  const std::vector<double> arcs = point_arcs_mm(seg);
  const double kappa_mm2 = kClotPermeability_m2 * 1e6;
  const double open_scale = std::sqrt(open_fraction);  // radius of a channel of that area share
  double darcy = 0.0, channel = 0.0;
  ClotResistance r;
  for (std::size_t j = 0; j + 1 < arcs.size(); ++j) {
    const double lo = std::max(a, arcs[j]);
    const double hi = std::min(b, arcs[j + 1]);
    if (!(hi > lo)) continue;
    const double r0 = radius_at_mm(seg, arcs, lo);
    const double r1 = radius_at_mm(seg, arcs, hi);
    const double len = hi - lo;
    r.lumen += cone_resistance(r0, r1, len, mu_Pa_s);
    darcy += mu_Pa_s * len / (kappa_mm2 * std::numbers::pi * r0 * r1);  // integral of mu / (kappa pi r^2) dx
    if (open_scale > 0.0) channel += cone_resistance(open_scale * r0, open_scale * r1, len, mu_Pa_s);
  }
  r.clot = channel > 0.0 ? 1.0 / (1.0 / darcy + 1.0 / channel) : darcy;
  return r;
}

std::string check_clot(const vessel::VesselModel& model, const Clot& c, std::size_t k) {
  const std::string which = "clot " + std::to_string(k + 1) + ": ";
  if (c.segment >= model.segments.size()) return which + "no segment index " + std::to_string(c.segment) + " in the vessel model";
  if (const char* e = check_composition(c.composition); *e != '\0') return which + e;
  if (!(std::isfinite(c.open_fraction) && c.open_fraction >= 0.0 && c.open_fraction < 1.0)) {
    return which + "open fraction must be in [0, 1)";
  }
  const std::vector<double> arcs = point_arcs_mm(model.segments[c.segment]);
  if (!(std::isfinite(c.arc_start_mm) && std::isfinite(c.length_mm) && c.arc_start_mm >= 0.0 && c.length_mm > 0.0 &&
        c.arc_start_mm + c.length_mm <= arcs.back() + 1e-9)) {
    return which + "must lie within segment " + std::to_string(model.segments[c.segment].id) + " (0 to " +
           std::to_string(arcs.back()) + " mm along it)";
  }
  return {};
}

}  // namespace

double catheter_resistance_Pa_s_per_mm3(double length_mm, double inner_diameter_mm, double viscosity_mPa_s) {
  const double d2 = inner_diameter_mm * inner_diameter_mm;
  return 128.0 * viscosity_mPa_s * 1e-3 * length_mm / (std::numbers::pi * d2 * d2);
}

base::Status<> FlowNetwork::occlude(std::span<const Clot> clots, std::span<const FlowArrest> arrests,
                                    std::span<const AspirationSink> sinks) {
  for (const FlowArrest& a : arrests) {
    if (a.segment >= model_.segments.size()) return base::Error{"flow: balloon: no segment index " + std::to_string(a.segment) + " in the vessel model"};
  }
  std::vector<int> sink_nodes;
  for (const AspirationSink& s : sinks) {
    if (s.segment >= model_.segments.size()) return base::Error{"flow: aspiration: no segment index " + std::to_string(s.segment) + " in the vessel model"};
    if (!(std::isfinite(s.resistance_Pa_s_per_mm3) && s.resistance_Pa_s_per_mm3 > 0.0 && std::isfinite(s.vacuum_Pa) && s.vacuum_Pa <= 0.0)) {
      return base::Error{"flow: aspiration: the catheter's resistance must be > 0 and its vacuum <= 0 Pa"};
    }
    sink_nodes.push_back(nearer_node(s.segment, s.arc_mm));
  }
  for (std::size_t k = 0; k < clots.size(); ++k) {
    if (std::string e = check_clot(model_, clots[k], k); !e.empty()) return base::Error{"flow: " + e};
    for (std::size_t m = 0; m < k; ++m) {
      const Clot& a = clots[m];
      const Clot& b = clots[k];
      if (a.segment == b.segment && a.arc_start_mm < b.arc_start_mm + b.length_mm && b.arc_start_mm < a.arc_start_mm + a.length_mm) {
        return base::Error{"flow: clots " + std::to_string(m + 1) + " and " + std::to_string(k + 1) + " overlap"};
      }
    }
  }
  const double mu = settings_.viscosity_mPa_s * 1e-3;
  std::vector<double> resistance = open_resistance_Pa_s_per_mm3_;
  for (const Clot& c : clots) {
    const ClotResistance r = clot_resistance(model_.segments[c.segment], c.arc_start_mm, c.arc_start_mm + c.length_mm, c.open_fraction, mu);
    resistance[c.segment] = std::max(resistance[c.segment] - r.lumen, 0.0) + r.clot;
  }
  for (const FlowArrest& a : arrests) resistance[a.segment] = kSealFactor * open_resistance_Pa_s_per_mm3_[a.segment];
  const std::vector<SegmentFlow> before = segments_;
  std::vector<AspirationSink> sinks_before(sinks.begin(), sinks.end());
  std::vector<int> nodes_before = sink_nodes;
  sinks_before.swap(sinks_);
  nodes_before.swap(sink_nodes_);
  for (std::size_t i = 0; i < segments_.size(); ++i) segments_[i].resistance_Pa_s_per_mm3 = std::max(resistance[i], kMinResistance);
  if (base::Status<> solved = solve_pressures(); !solved) {
    segments_ = before;
    sinks_ = std::move(sinks_before);
    sink_nodes_ = std::move(nodes_before);
    return solved;
  }
  clots_.assign(clots.begin(), clots.end());
  arrests_.assign(arrests.begin(), arrests.end());
  return base::Ok{};
}

int FlowNetwork::nearer_node(std::uint32_t segment, double arc_mm) const {
  const SegmentFlow& f = segments_[segment];
  return arc_mm <= 0.5 * f.length_mm ? f.start_node : f.end_node;
}

double FlowNetwork::sink_flow_at_mm3_s(int node) const {
  double q = 0.0;
  for (std::size_t k = 0; k < sinks_.size(); ++k) {
    if (sink_nodes_[k] == node) q += sink_flow_ml_min(k) / 0.06;
  }
  return q;
}

double FlowNetwork::sink_flow_ml_min(std::size_t k) const {
  const double p = pressure_Pa_[static_cast<std::size_t>(sink_nodes_[k])];
  return 0.06 * (p - sink_pressure_Pa(sinks_[k])) / sinks_[k].resistance_Pa_s_per_mm3;
}

double FlowNetwork::sink_pressure_Pa(const AspirationSink& s) const {
  return s.vacuum_Pa - settings_.venous_pressure_mmHg * kPa_per_mmHg;
}

}  // namespace cathbox::flow
