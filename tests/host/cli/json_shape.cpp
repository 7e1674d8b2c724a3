// cli_json_shape SHAPE: checks that standard input is the `cathbox ... --json` output of one
// command in the shape host/cli/README.md documents ("JSON output"): every key, in order, and
// the type of every value. Exit 0 when it is; else 1 with one line per difference.
//   monitor: every line is one object; every other shape: the whole input is one value.
// A shape is JSON: "string", "integer", "number" (integer or not), "boolean", "null", or
// alternatives joined by '|'; an object lists its keys in order ({"*": T}: any keys, each a T;
// "?": true first: the value may also be null); an array lists the shapes an item may take.
#include <cstdio>
#include <iostream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace {

using nlohmann::ordered_json;

const char* const kShapes = R"({
 "list": [{"kind": "string", "path": "string", "serial": "string"},
          {"kind": "string", "usb": "string"},
          {"kind": "string", "socket": "string", "serial": "string"},
          {"kind": "string", "socket": "string"}],
 "info": {"transport": "string", "firmware": "string", "protocol": "string", "serial": "string",
          "board": "string", "insertion_actuator": "string", "rotation_actuator": "string",
          "insertion_encoder_cpr": "integer", "rotation_encoder_cpr": "integer",
          "calibration": {"insertion_counts_per_m": "integer", "rotation_counts_per_rev": "integer",
                          "insertion_full_scale_mN": "integer", "rotation_full_scale_uNm": "integer"},
          "limits": {"max_force_mN": "integer", "max_torque_uNm": "integer", "watchdog_timeout_ms": "integer",
                     "insertion_max_current_mA": "integer", "rotation_max_current_mA": "integer",
                     "force_slew_mN_per_ms": "integer", "torque_slew_uNm_per_ms": "integer"},
          "status": "string", "faults": "string", "mode": "string"},
 "monitor": {"t_s": "number", "insertion_count": "integer", "insertion_mm": "number",
             "insertion_mm_s": "number", "insertion_force_mN": "integer", "rotation_count": "integer",
             "rotation_deg": "number", "rotation_deg_s": "number", "rotation_torque_uNm": "integer",
             "insertion_current_mA": "integer", "rotation_current_mA": "integer", "mode": "string",
             "status": "string", "faults": "string", "encoder_errors": "integer", "rx_errors": "integer",
             "report_rate_hz": "number", "host_rejected": "integer", "link_up": "boolean"},
 "calibrate": {"insertion_counts": "integer", "rotation_counts": "integer",
               "insertion_counts_per_m": "integer", "rotation_counts_per_rev": "integer"},
 "selftest": {"result": "string", "failed_checks": "string", "insertion_current_mA": "integer",
              "rotation_current_mA": "integer", "supply_mV": "integer"},
 "vessel-info": {"file": "string", "segments": "integer", "points": "integer", "junctions": "integer",
                 "junction_kinds": {"*": "integer"}, "free_ends": "integer", "components": "integer",
                 "cycles": "integer", "total_length_mm": "number", "radius_min_mm": "number",
                 "radius_max_mm": "number"},
 "flow-info": {"file": "string",
               "settings": {"viscosity_mPa_s": "number", "cardiac_output_ml_min": "number",
                            "cerebral_fraction": "number", "arterial_pressure_mmHg": "number",
                            "venous_pressure_mmHg": "number", "wall_shear_stress_Pa": "number",
                            "dispersion_radii": "number", "sac_exchange_fraction": "number",
                            "heart_rate_bpm": "number", "pulsatility_index": "number"},
               "total_inflow_ml_min": "number",
               "segments": [{"id": "integer", "name": "string", "flow_ml_min": "number",
                             "mean_velocity_mm_s": "number", "peak_velocity_mm_s": "number",
                             "reynolds": "number", "length_mm": "number", "volume_ml": "number",
                             "resistance_Pa_s_per_mm3": "number", "pressure_start_mmHg": "number",
                             "pressure_end_mmHg": "number"}],
               "terminals": [{"segment_id": "integer", "end": "string", "role": "string",
                              "territory": "string", "overridden": "boolean", "target_ml_min": "number",
                              "flow_ml_min": "number"}]},
 "session-info": {"file": "string", "bytes": "integer", "blocks": "integer", "software_version": "string",
                  "start_unix_us": "integer",
                  "case": {"name": "string", "file": "string", "bytes": "integer"},
                  "vessel": {"file": "string", "bytes": "integer"},
                  "surface": {"file": "string", "bytes": "integer"},
                  "tools": [{"name": "string", "kind": "string", "length_mm": "number", "sections": "integer",
                             "inside": "string"}],
                  "entry": {"point_mm": ["number"], "direction": ["number"]},
                  "held_tool": "integer",
                  "hand": {"kind": "string", "description": "string"},
                  "device": {"?": true, "description": "string", "serial": "string", "board": "string",
                                      "firmware": "string", "insertion_counts_per_m": "integer",
                                      "rotation_counts_per_rev": "integer", "insertion_full_scale_mN": "integer",
                                      "rotation_full_scale_uNm": "integer", "insertion_actuator": "integer",
                                      "rotation_actuator": "integer"},
                  "period_us": "integer", "hash_every": "integer", "ticks": "integer", "duration_s": "number",
                  "state_hashes": "integer", "controls": {"*": "integer"}, "box_status_changes": "integer",
                  "target_reached_tick": "integer|null", "finished": "boolean",
                  "end": {"?": true, "reason": "string", "text": "string", "end_unix_us": "integer",
                          "haptic_dropped_ticks": "integer|null"},
                  "error": "string|null"},
 "session-metrics": {"ticks": "integer", "hashes_checked": "integer", "procedure_time_s": "number",
                     "has_target": "boolean", "target_reached": "boolean", "time_to_target_s": "number|null",
                     "closest_to_target_mm": "number|null", "tip_path_mm": "number",
                     "route_length_mm": "number|null", "path_efficiency": "number|null",
                     "wall_contacts": "integer", "peak_wall_force_mN": "number",
                     "wall_force_threshold_mN": "number", "time_above_threshold_s": "number",
                     "wrong_branch_entries": "integer|null", "retractions": "integer",
                     "peak_insertion_speed_mm_s": "number", "tool_changes": "integer",
                     "peak_hand_force_mN": "number", "unconverged_pct": {"*": "number"},
                     "fluoroscopy_time_s": "number|null", "dose_area_product_mGy_cm2": "number|null", "fluoroscopy_runs": "integer|null",
                     "contrast_volume_ml": "number|null", "packing_density_pct": "number|null",
                     "coil_length_mm": "number|null", "coil_herniations": "integer|null",
                     "coil_herniated_peak_nodes": "integer|null", "coil_herniated_depth_mm": "number|null",
                     "kick_back_mm": "number|null", "kick_forward_mm": "number|null",
                     "coil_detach_force_mN": ["number"], "coil_detach_force_peak_mN": "number|null",
                     "coil_detached_under_tension": "integer|null", "coil_sleep_skipped_steps": "integer|null",
                     "coil_sleep_wakes": "integer|null", "stenosis_before_pct": "number|null",
                     "residual_stenosis_pct": "number|null", "balloon_inflations": "integer|null",
                     "balloon_inflated_s": "number|null", "rupture_risk_events": "integer|null",
                     "thrombectomy": {"?": true, "passes": "integer",
                                      "etici_per_pass": [{"etici": "string", "reperfused_pct": "number"}],
                                      "etici_final": "string", "reperfused_pct_final": "number",
                                      "first_pass_effect": "boolean", "emboli": "integer",
                                      "emboli_new_territory": "integer", "emboli_lodged": ["string"],
                                      "emboli_in_transit": [{"at": "string", "at_mm": "number",
                                                             "would_lodge": "string|null", "new_territory": "boolean"}],
                                      "time_to_reperfusion_s": "number|null",
                                      "balloon_guide_inflations": "integer", "flow_arrest_s": "number",
                                      "stent_passes": "integer", "retrieval_force_peak_N": "number|null"},
                     "haptic_dropped_ticks": "integer|null"}
})";

bool is_type(const ordered_json& v, const std::string& type) {
  std::istringstream alternatives(type);
  for (std::string t; std::getline(alternatives, t, '|');) {
    if ((t == "string" && v.is_string()) || (t == "integer" && v.is_number_integer()) ||
        (t == "number" && v.is_number()) || (t == "boolean" && v.is_boolean()) || (t == "null" && v.is_null())) {
      return true;
    }
  }
  return false;
}

// Appends one line per difference between `v` and `shape` at `where` to `out`.
void check(const ordered_json& v, const ordered_json& shape, const std::string& where, std::string& out) {
  if (shape.is_string()) {
    if (!is_type(v, shape.get<std::string>())) out += where + ": " + v.type_name() + ", want " + shape.get<std::string>() + "\n";
    return;
  }
  if (shape.is_array()) {
    if (!v.is_array()) {
      out += where + ": " + v.type_name() + ", want an array\n";
      return;
    }
    for (std::size_t i = 0; i < v.size(); ++i) {
      std::string best;
      for (const ordered_json& item : shape) {
        std::string diff;
        check(v[i], item, where + "[" + std::to_string(i) + "]", diff);
        if (diff.empty()) {
          best.clear();
          break;
        }
        if (best.empty()) best = diff;
      }
      out += best;
    }
    return;
  }
  if (shape.contains("?") && v.is_null()) return;  // an object that may be null
  if (!v.is_object()) {
    out += where + ": " + v.type_name() + ", want an object\n";
    return;
  }
  if (shape.contains("*")) {
    for (const auto& [key, value] : v.items()) check(value, shape["*"], where + "." + key, out);
    return;
  }
  auto want = shape.begin();
  auto got = v.begin();
  if (want != shape.end() && want.key() == "?") ++want;
  for (; want != shape.end() && got != v.end(); ++want, ++got) {
    if (want.key() != got.key()) {
      out += where + ": key '" + got.key() + "' where '" + want.key() + "' belongs\n";
      return;
    }
    check(got.value(), want.value(), where + "." + got.key(), out);
  }
  if (want != shape.end()) out += where + ": key '" + want.key() + "' missing\n";
  if (got != v.end()) out += where + ": key '" + got.key() + "' not in the shape\n";
}

}  // namespace

int main(int argc, char** argv) {
  const ordered_json shapes = ordered_json::parse(kShapes);
  if (argc != 2 || !shapes.contains(argv[1])) {
    std::fprintf(stderr, "usage: cli_json_shape SHAPE < OUTPUT   (SHAPE: list, info, monitor, ...)\n");
    return 2;
  }
  const std::string name = argv[1];
  const std::string input((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
  std::vector<std::string> documents;
  if (name == "monitor") {
    std::istringstream lines(input);
    for (std::string line; std::getline(lines, line);) {
      if (!line.empty()) documents.push_back(line);
    }
  } else {
    documents.push_back(input);
  }
  if (documents.empty()) {
    std::fprintf(stderr, "cli_json_shape %s: no output\n", name.c_str());
    return 1;
  }
  std::string out;
  for (std::size_t i = 0; i < documents.size(); ++i) {
    const ordered_json v = ordered_json::parse(documents[i], nullptr, false);
    if (v.is_discarded()) {
      out += "document " + std::to_string(i) + ": not JSON\n";
      continue;
    }
    check(v, shapes[name], name, out);
  }
  std::fputs(out.c_str(), stderr);
  return out.empty() ? 0 : 1;
}
