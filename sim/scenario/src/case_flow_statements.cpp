// The case file's `flow` statements (the blood-flow model's settings) and `clot` statements.
#include "case_parser.hpp"

#include <cmath>

namespace cathbox::tool::detail {

// `flow KEY VALUES...`: the blood-flow model's settings (sim/flow/README.md). Segment ids are
// checked against the vessel model when the flow network is built, naming this line.
bool CaseParser::flow_statement(flow::FlowSettings& f, const std::vector<std::string_view>& w) {
  if (w.size() < 2) return error_here("flow: missing setting (viscosity cardiac_output cerebral_fraction pressure "
                                      "wall_shear_stress dispersion pulsatile terminals inflow outlet closed)");
  const std::string_view key = w[1];
  if (key == "viscosity") return flow_scalar(w, f.viscosity_mPa_s, 0.5, 20.0, false, "[0.5, 20] mPa.s");
  if (key == "cardiac_output") return flow_scalar(w, f.cardiac_output_ml_min, 500.0, 40000.0, false, "[500, 40000] mL/min");
  if (key == "cerebral_fraction") return flow_scalar(w, f.cerebral_fraction, 0.0, 0.5, true, "(0, 0.5]");
  if (key == "wall_shear_stress") return flow_scalar(w, f.wall_shear_stress_Pa, 0.0, 20.0, true, "(0, 20] Pa");
  if (key == "dispersion") return flow_scalar(w, f.dispersion_radii, 0.0, 20.0, false, "[0, 20] radii");
  if (key == "pressure") {
    if (!flow_args(w, 2, 2) || !once_flow(key) || !flow_value_in(w, 2, 20.0, 250.0, false, "[20, 250] mmHg", f.arterial_pressure_mmHg) ||
        !flow_value_in(w, 3, 0.0, 50.0, false, "[0, 50] mmHg", f.venous_pressure_mmHg)) {
      return false;
    }
    if (f.venous_pressure_mmHg >= f.arterial_pressure_mmHg) return error_here("flow pressure: venous must be below arterial pressure");
    return true;
  }
  if (key == "pulsatile") {
    return flow_args(w, 2, 2) && once_flow(key) && flow_value_in(w, 2, 0.0, 300.0, true, "(0, 300] bpm", f.heart_rate_bpm) &&
           flow_value_in(w, 3, 0.0, 2.0, false, "[0, 2]", f.pulsatility_index);
  }
  if (key == "terminals") {
    if (!flow_args(w, 1, 1) || !once_flow(key)) return false;
    if (w[2] != "calibrated" && w[2] != "fixed") {
      return error_here("flow terminals: expected 'calibrated' or 'fixed', not '" + std::string(w[2]) + "'");
    }
    f.calibrate_terminals = w[2] == "calibrated";
    return true;
  }
  double v = 0.0;
  if (key == "inflow" || key == "outlet") {
    const bool outlet = key == "outlet";
    if (!flow_args(w, 2, 2) || !flow_value_in(w, 3, 0.0, 40000.0, outlet, outlet ? "(0, 40000] mL/min" : "[0, 40000] mL/min", v)) {
      return false;
    }
    return flow_segment_setting(f, w, outlet ? f.outlets : f.inflows, v);
  }
  if (key == "closed") {
    v = f.sac_exchange_fraction;
    if (!flow_args(w, 1, 2) || (w.size() == 4 && !flow_value_in(w, 3, 0.0, 1.0, false, "[0, 1]", v))) return false;
    return flow_segment_setting(f, w, f.closed, v);
  }
  return error_here("flow: unknown setting '" + std::string(key) +
                    "' (known: viscosity cardiac_output cerebral_fraction pressure wall_shear_stress dispersion "
                    "pulsatile terminals inflow outlet closed)");
}

// `flow KEY ...` has lo..hi values after its key.
bool CaseParser::flow_args(const std::vector<std::string_view>& w, std::size_t lo, std::size_t hi) {
  const std::size_t n = w.size() - 2;
  if (n >= lo && n <= hi) return true;
  return error_here("flow " + std::string(w[1]) + ": expected " + std::to_string(lo) + (hi > lo ? " or " + std::to_string(hi) : "") +
                    " value" + (hi == 1 ? "" : "s") + ", got " + std::to_string(n));
}

// Word i of a flow line, a number in the range (lo open or closed, hi closed).
bool CaseParser::flow_value_in(const std::vector<std::string_view>& w, std::size_t i, double lo, double hi, bool lo_open, const char* range,
                             double& out) {
  const std::string what = "flow " + std::string(w[1]);
  if (!number(w[i], what, out)) return false;
  if ((lo_open ? out <= lo : out < lo) || out > hi) return error_here(what + ": " + std::string(w[i]) + " is not in " + range);
  return true;
}

// `flow KEY VALUE`, once per case.
bool CaseParser::flow_scalar(const std::vector<std::string_view>& w, double& field, double lo, double hi, bool lo_open, const char* range) {
  if (!flow_args(w, 1, 1) || !once_flow(w[1])) return false;
  return flow_value_in(w, 2, lo, hi, lo_open, range, field);
}

// `flow inflow|outlet|closed SEG ...`: a segment given once as an outlet or closed (an
// inflow may also be either), at most kMaxFlowSettings in all.
bool CaseParser::flow_segment_setting(flow::FlowSettings& f, const std::vector<std::string_view>& w, std::vector<flow::SegmentSetting>& list,
                                    double value) {
  const std::string what = "flow " + std::string(w[1]);
  double id = 0.0;
  if (!number(w[2], what, id)) return false;
  if (id != std::floor(id) || id < -2147483648.0 || id > 2147483647.0) return error_here(what + ": segment id must be a 32-bit integer");
  const auto seg = static_cast<std::int32_t>(id);
  for (const auto* other : {&f.inflows, &f.outlets, &f.closed}) {
    for (const flow::SegmentSetting& o : *other) {
      const bool same_list = other == &list;
      const bool clash = same_list || (other != &f.inflows && &list != &f.inflows);
      if (o.segment_id == seg && clash) {
        return error_here(what + ": segment " + std::to_string(seg) + " already given on line " + std::to_string(o.line));
      }
    }
  }
  if (f.inflows.size() + f.outlets.size() + f.closed.size() >= kMaxFlowSettings) return error_here("too many flow settings");
  list.push_back(flow::SegmentSetting{seg, value, lines_.line()});
  return true;
}

bool CaseParser::once_flow(std::string_view key) {
  for (const std::string& k : flow_keys_) {
    if (k == key) return error_here("flow " + std::string(key) + " given twice");
  }
  flow_keys_.emplace_back(key);
  return true;
}

// `clot SEG FROM_MM LENGTH_MM [red=PCT] [fibrin=PCT] [open=F]`.
bool CaseParser::clot_statement(Case& c, const std::vector<std::string_view>& w) {
  if (w.size() < 4) return error_here("clot: expected SEG FROM_MM LENGTH_MM [red=PCT] [fibrin=PCT] [open=F]");
  if (c.clots.size() >= kMaxClots) return error_here("too many clots (at most 16)");
  double v[3];
  if (!numbers(w, 1, v, 3)) return false;
  if (v[0] != std::floor(v[0]) || v[0] < 0 || v[0] > 2e9) return error_here("clot: segment id must be an integer >= 0");
  if (v[1] < 0.0 || v[1] > 1000.0) return error_here("clot: start must be in [0, 1000] mm along the segment");
  if (v[2] <= 0.0 || v[2] > 100.0) return error_here("clot: length must be in (0, 100] mm");
  CaseClot clot{static_cast<std::int32_t>(v[0]), v[1], v[2], flow::kReferenceComposition, 0.0, lines_.line()};
  const bool pairs = number_pairs(w, 4, "clot", [&](std::string_view k, double x) {
    if (k == "red") {
      clot.composition.red_cell_percent = x;
    } else if (k == "fibrin") {
      clot.composition.fibrin_platelet_percent = x;
    } else if (k == "open") {
      if (x < 0.0 || x >= 1.0) return error_here("clot: open must be in [0, 1)");
      clot.open_fraction = x;
    } else {
      return error_here("clot: unknown key '" + std::string(k) + "' (known: red fibrin open)");
    }
    return true;
  });
  if (!pairs) return false;
  if (const char* e = flow::check_composition(clot.composition); *e != '\0') return error_here(e);
  c.clots.push_back(clot);
  return true;
}

}  // namespace cathbox::tool::detail
