#include "session_json.hpp"

#include <algorithm>
#include <cstdio>

#include "session/control.hpp"

namespace cathbox::cli {
namespace {

using json = nlohmann::ordered_json;

json optional_number(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

std::string control_name(std::uint16_t kind) {
  if (const char* name = session::control_kind_name(kind)) return name;
  return "kind_" + std::to_string(kind);
}

}  // namespace

RecordSummary summarise(session::RecordReader& reader) {
  RecordSummary s;
  session::TickRecord t;
  while (reader.next(t)) {
    if (t.state_hash) ++s.hashes;
    if (t.box_changed) ++s.box_changes;
    for (std::size_t i = 0; i < t.control_count; ++i) ++s.controls[t.controls[i].kind];
    for (std::size_t i = 0; i < t.event_count; ++i) {
      if (t.events[i] == session::record::EventCode::kTargetReached && s.target_reached_tick < 0) s.target_reached_tick = t.tick;
    }
  }
  s.ticks = reader.ticks_read();
  return s;
}

json info_json(const std::string& path, const session::RecordReader& reader, const RecordSummary& s) {
  const session::RecordHeader& h = reader.header();
  json tools = json::array();
  for (const tool::ToolSpec& t : h.tools) {
    tools.push_back({{"name", t.name},
                     {"kind", t.kind == tool::ToolKind::kCatheter ? "catheter" : t.kind == tool::ToolKind::kCoil ? "coil" : "guidewire"},
                     {"length_mm", t.length_mm()},
                     {"sections", t.sections.size()},
                     {"inside", t.inside}});
  }
  json device = nullptr;
  if (h.device) {
    const session::DeviceRecord& d = *h.device;
    device = {{"description", d.description},
              {"serial", d.serial},
              {"board", d.board},
              {"firmware", d.firmware},
              {"insertion_counts_per_m", d.insertion_counts_per_m},
              {"rotation_counts_per_rev", d.rotation_counts_per_rev},
              {"insertion_full_scale_mN", d.insertion_full_scale_mN},
              {"rotation_full_scale_uNm", d.rotation_full_scale_uNm},
              {"insertion_actuator", d.insertion_actuator},
              {"rotation_actuator", d.rotation_actuator}};
  }
  json controls = json::object();
  for (const auto& [kind, n] : s.controls) controls[control_name(kind)] = n;
  json end = nullptr;
  if (reader.end()) {
    end = {{"reason", session::record::end_reason_name(reader.end()->reason)},
           {"text", reader.end()->text},
           {"end_unix_us", reader.end()->end_unix_us},
           {"haptic_dropped_ticks", reader.end()->haptic_dropped_ticks ? json(*reader.end()->haptic_dropped_ticks) : json(nullptr)}};
  }
  return {{"file", path},
          {"bytes", reader.bytes_read()},
          {"blocks", reader.blocks_read()},
          {"software_version", h.software_version},
          {"start_unix_us", h.start_unix_us},
          {"case", {{"name", h.case_name}, {"file", h.case_file}, {"bytes", h.case_text.size()}}},
          {"vessel", {{"file", h.vessel_file}, {"bytes", h.vessel_text.size()}}},
          {"surface", {{"file", h.surface_file}, {"bytes", h.surface_bytes.size()}}},
          {"tools", tools},
          {"entry", {{"point_mm", {h.entry.point_mm.x, h.entry.point_mm.y, h.entry.point_mm.z}},
                     {"direction", {h.entry.direction.x, h.entry.direction.y, h.entry.direction.z}}}},
          {"held_tool", h.held_tool},
          {"hand", {{"kind", session::hand_kind_name(h.hand)}, {"description", h.hand_description}}},
          {"device", device},
          {"period_us", h.period_us},
          {"hash_every", h.hash_every},
          {"ticks", s.ticks},
          {"duration_s", static_cast<double>(s.ticks * h.period_us) * 1e-6},
          {"state_hashes", s.hashes},
          {"controls", controls},
          {"box_status_changes", s.box_changes},
          {"target_reached_tick", s.target_reached_tick >= 0 ? json(s.target_reached_tick) : json(nullptr)},
          {"finished", reader.end().has_value()},
          {"end", end},
          {"error", reader.error().empty() ? json(nullptr) : json(reader.error())}};
}

std::string info_text(const std::string& path, const session::RecordReader& reader, const RecordSummary& s) {
  const session::RecordHeader& h = reader.header();
  std::string out;
  char line[512];
  auto add = [&](const char* name, const std::string& value) {
    std::snprintf(line, sizeof line, "%-16s %s\n", name, value.c_str());
    out += line;
  };
  add("record", path + " (" + std::to_string(reader.bytes_read()) + " bytes, " + std::to_string(reader.blocks_read()) + " blocks)");
  add("software", h.software_version);
  add("case", h.case_name + (h.case_file.empty() ? "" : " (" + h.case_file + ")"));
  add("vessel", h.vessel_file.empty() ? "analytic tubes" : h.vessel_file + " (" + std::to_string(h.vessel_text.size()) + " bytes)");
  if (!h.surface_file.empty()) add("surface", h.surface_file + " (" + std::to_string(h.surface_bytes.size()) + " bytes)");
  std::string tools;
  for (const tool::ToolSpec& t : h.tools) tools += (tools.empty() ? "" : ", ") + t.name;
  add("tools", tools + " (held: " + h.tools[h.held_tool].name + ")");
  add("hand", std::string(session::hand_kind_name(h.hand)) + ": " + h.hand_description);
  if (h.device) {
    add("box", h.device->description + ", serial " + h.device->serial + ", firmware " + h.device->firmware + ", " +
                   std::to_string(h.device->insertion_counts_per_m) + " counts/m, " +
                   std::to_string(h.device->rotation_counts_per_rev) + " counts/rev");
  }
  std::snprintf(line, sizeof line, "%lld ticks of %lld us (%.3f s), %lld state hashes", static_cast<long long>(s.ticks),
                static_cast<long long>(h.period_us), static_cast<double>(s.ticks * h.period_us) * 1e-6,
                static_cast<long long>(s.hashes));
  add("length", line);
  std::string controls;
  for (const auto& [kind, n] : s.controls) controls += (controls.empty() ? "" : ", ") + control_name(kind) + " " + std::to_string(n);
  add("controls", controls.empty() ? "none" : controls);
  if (s.target_reached_tick >= 0) add("target", "reached at tick " + std::to_string(s.target_reached_tick));
  if (reader.end()) {
    add("end", std::string(session::record::end_reason_name(reader.end()->reason)) +
                   (reader.end()->text.empty() ? "" : ": " + reader.end()->text));
    if (reader.end()->haptic_dropped_ticks) {
      add("real time", "paced in real time, " + std::to_string(*reader.end()->haptic_dropped_ticks) + " haptic ticks dropped");
    }
  } else {
    add("end", "none: the recording process stopped (killed?); readable to its last complete block");
  }
  return out;
}

json metrics_json(const session::ReplayResult& r) {
  const session::Metrics& m = r.metrics;
  auto or_null = [](bool present, double v) { return present ? json(v) : json(nullptr); };
  // Per tool: the share of its steps that ran out of Newton iterations (%).
  json unconverged = json::object();
  for (const session::ToolConvergence& c : m.convergence) unconverged[c.tool] = c.unconverged_pct();
  // A thrombectomy case's figures (host/session/README.md, "Thrombectomy"), else null.
  json thrombectomy = nullptr;
  if (m.thrombectomy) {
    const session::ThrombectomyFigures& t = *m.thrombectomy;
    json passes = json::array();
    const std::size_t graded = std::min<std::size_t>(static_cast<std::size_t>(t.passes), session::ThrombectomyFigures::kMaxPasses);
    for (std::size_t i = 0; i < graded; ++i) {
      passes.push_back({{"etici", std::string(flow::etici_label(t.etici_after_pass[i]))}, {"reperfused_pct", t.reperfused_pct_after_pass[i]}});
    }
    json in_transit = json::array();
    for (const session::EmbolusInTransit& e : t.emboli_in_transit) {
      in_transit.push_back({{"at", e.at}, {"at_mm", e.at_mm}, {"would_lodge", e.would_lodge.empty() ? json(nullptr) : json(e.would_lodge)},
                            {"new_territory", e.new_territory}});
    }
    thrombectomy = {{"passes", t.passes},
                    {"etici_per_pass", passes},
                    {"etici_final", std::string(flow::etici_label(t.etici_final))},
                    {"reperfused_pct_final", t.reperfused_pct_final},
                    {"first_pass_effect", t.first_pass_effect},
                    {"emboli", t.emboli},
                    {"emboli_new_territory", t.emboli_new_territory},
                    {"emboli_lodged", t.emboli_lodged},
                    {"emboli_in_transit", in_transit},
                    {"time_to_reperfusion_s", or_null(t.time_to_reperfusion_us >= 0, static_cast<double>(t.time_to_reperfusion_us) * 1e-6)},
                    {"balloon_guide_inflations", t.balloon_guide_inflations},
                    {"flow_arrest_s", t.flow_arrest_s},
                    {"stent_passes", t.stent_passes},
                    {"retrieval_force_peak_N", or_null(t.stent_passes > 0, t.retrieval_force_peak_N)}};
  }
  return {{"ticks", r.ticks},
          {"hashes_checked", r.hashes_checked},
          {"procedure_time_s", static_cast<double>(m.procedure_time_us) * 1e-6},
          {"has_target", m.has_target},
          {"target_reached", m.target_reached},
          {"time_to_target_s", or_null(m.target_reached, static_cast<double>(m.time_to_target_us) * 1e-6)},
          {"closest_to_target_mm", or_null(m.has_target, m.closest_to_target_mm)},
          {"tip_path_mm", m.tip_path_mm},
          {"route_length_mm", or_null(m.route_length_mm >= 0.0, m.route_length_mm)},
          {"path_efficiency", or_null(m.path_efficiency > 0.0, m.path_efficiency)},
          {"wall_contacts", m.wall_contacts},
          {"peak_wall_force_mN", m.peak_wall_force_mN},
          {"wall_force_threshold_mN", m.wall_force_threshold_mN},
          {"time_above_threshold_s", static_cast<double>(m.time_above_threshold_us) * 1e-6},
          {"wrong_branch_entries", m.wrong_branch_entries >= 0 ? json(m.wrong_branch_entries) : json(nullptr)},
          {"retractions", m.retractions},
          {"peak_insertion_speed_mm_s", m.peak_insertion_speed_mm_s},
          {"tool_changes", m.tool_changes},
          {"peak_hand_force_mN", m.peak_hand_force_mN},
          {"unconverged_pct", unconverged},
          {"fluoroscopy_time_s", optional_number(m.fluoroscopy_time_s)},
          {"dose_area_product_mGy_cm2", optional_number(m.dose_area_product_mGy_cm2)},
          {"fluoroscopy_runs", m.fluoroscopy_runs ? json(*m.fluoroscopy_runs) : json(nullptr)},
          {"contrast_volume_ml", optional_number(m.contrast_volume_ml)},
          {"packing_density_pct", optional_number(m.packing_density_pct)},
          {"coil_length_mm", optional_number(m.coil_length_mm)},
          {"coil_herniations", m.coil_herniations ? json(*m.coil_herniations) : json(nullptr)},
          {"coil_herniated_peak_nodes", m.coil_herniated_peak_nodes ? json(*m.coil_herniated_peak_nodes) : json(nullptr)},
          {"coil_herniated_depth_mm", optional_number(m.coil_herniated_depth_mm)},
          {"kick_back_mm", optional_number(m.kick_back_mm)},
          {"kick_forward_mm", optional_number(m.kick_forward_mm)},
          {"coil_detach_force_mN", json(m.coil_detach_force_mN)},
          {"coil_detach_force_peak_mN", optional_number(m.coil_detach_force_peak_mN)},
          {"coil_detached_under_tension", m.coil_detached_under_tension ? json(*m.coil_detached_under_tension) : json(nullptr)},
          {"coil_sleep_skipped_steps", m.coil_sleep_skipped_steps ? json(*m.coil_sleep_skipped_steps) : json(nullptr)},
          {"coil_sleep_wakes", m.coil_sleep_wakes ? json(*m.coil_sleep_wakes) : json(nullptr)},
          {"stenosis_before_pct", optional_number(m.stenosis_before_pct)},
          {"residual_stenosis_pct", optional_number(m.residual_stenosis_pct)},
          {"balloon_inflations", m.balloon_inflations ? json(*m.balloon_inflations) : json(nullptr)},
          {"balloon_inflated_s", optional_number(m.balloon_inflated_s)},
          {"rupture_risk_events", m.rupture_risk_events ? json(*m.rupture_risk_events) : json(nullptr)},
          {"thrombectomy", thrombectomy},
          {"haptic_dropped_ticks", m.haptic_dropped_ticks ? json(*m.haptic_dropped_ticks) : json(nullptr)}};
}

}  // namespace cathbox::cli
