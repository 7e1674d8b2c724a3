// The run's metrics as people and programs read them: the text of `session metrics` and the
// end of a headless run (MetricsCollector::format), and the named numbers the server stores,
// criteria judge and live frames carry (named_metrics, metric_names).
#include <algorithm>
#include <cstdarg>
#include <cstdio>

#include "session/metrics.hpp"

namespace cathbox::session {

namespace {

void appendf(std::string& out, const char* fmt, ...) __attribute__((format(printf, 2, 3)));
void appendf(std::string& out, const char* fmt, ...) {
  char buf[160];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  out += buf;
}

void format_thrombectomy(std::string& out, const ThrombectomyFigures& t) {
  appendf(out, "%-21s %d\n", "passes", t.passes);
  for (std::size_t i = 0; i < std::min<std::size_t>(static_cast<std::size_t>(t.passes), ThrombectomyFigures::kMaxPasses); ++i) {
    appendf(out, "eTICI after pass %-4zu %s (%.0f %%)\n", i + 1, std::string(flow::etici_label(t.etici_after_pass[i])).c_str(),
            t.reperfused_pct_after_pass[i]);
  }
  appendf(out, "%-21s %s (%.0f %%)\n", "eTICI final", std::string(flow::etici_label(t.etici_final)).c_str(), t.reperfused_pct_final);
  appendf(out, "%-21s %s\n", "first-pass effect", t.first_pass_effect ? "yes" : "no");
  appendf(out, "%-21s %d (%d to new territories)\n", "emboli", t.emboli, t.emboli_new_territory);
  for (const EmbolusInTransit& e : t.emboli_in_transit) {
    appendf(out, "  in transit in the %s at %.0f mm: %s%s%s\n", e.at.c_str(), e.at_mm,
            e.would_lodge.empty() ? "no flow carries it" : "would lodge in the ", e.would_lodge.c_str(), e.new_territory ? " (new territory)" : "");
  }
  if (t.time_to_reperfusion_us >= 0) {
    appendf(out, "%-21s %.1f s\n", "time to reperfusion", static_cast<double>(t.time_to_reperfusion_us) * 1e-6);
  } else {
    appendf(out, "%-21s n/a\n", "time to reperfusion");
  }
  appendf(out, "%-21s %d\n", "guide inflations", t.balloon_guide_inflations);
  appendf(out, "%-21s %.2f s\n", "flow arrest", t.flow_arrest_s);
  if (t.stent_passes > 0) appendf(out, "%-21s %.3f N (%d stent passes)\n", "retrieval force", t.retrieval_force_peak_N, t.stent_passes);
}

// One line of the coils' detachments: the pusher's force at each release, and how many of them
// were under tension (none printed before the first detachment).
void format_detach_forces(std::string& out, const Metrics& m) {
  if (m.coil_detach_force_mN.empty()) return;
  appendf(out, "%-21s", "detach force");
  for (std::size_t i = 0; i < m.coil_detach_force_mN.size(); ++i) appendf(out, "%s %+.1f", i == 0 ? "" : ",", m.coil_detach_force_mN[i]);
  appendf(out, " mN (%d under tension, over %.0f mN)\n", m.coil_detached_under_tension.value_or(0), tool::CoilMetrics::kNeutral_mN);
}

}  // namespace

std::string MetricsCollector::format(const Metrics& m) {
  std::string out;
  appendf(out, "procedure time        %.2f s\n", static_cast<double>(m.procedure_time_us) * 1e-6);
  appendf(out, "tip path length       %.1f mm\n", m.tip_path_mm);
  appendf(out, "wall contacts         %d\n", m.wall_contacts);
  appendf(out, "peak wall force       %.1f mN\n", m.peak_wall_force_mN);
  char above[32];
  std::snprintf(above, sizeof above, "time above %.0f mN", m.wall_force_threshold_mN);
  appendf(out, "%-21s %.2f s\n", above, static_cast<double>(m.time_above_threshold_us) * 1e-6);
  if (m.wrong_branch_entries >= 0) {
    appendf(out, "wrong-branch entries  %d\n", m.wrong_branch_entries);
  } else {
    appendf(out, "wrong-branch entries  n/a (no target)\n");
  }
  appendf(out, "retractions           %d\n", m.retractions);
  appendf(out, "peak insertion speed  %.1f mm/s\n", m.peak_insertion_speed_mm_s);
  appendf(out, "tool changes          %d\n", m.tool_changes);
  appendf(out, "peak hand force       %.1f mN\n", m.peak_hand_force_mN);
  for (const ToolConvergence& c : m.convergence) {
    appendf(out, "unconverged           %.2f %% of %lld ticks (%s)\n", c.unconverged_pct(),
            static_cast<long long>(c.solved_ticks), c.tool.c_str());
  }
  if (!m.has_target) {
    appendf(out, "target                none in this case\n");
  } else if (m.target_reached) {
    appendf(out, "target                reached at %.2f s\n", static_cast<double>(m.time_to_target_us) * 1e-6);
  } else {
    appendf(out, "target                not reached (closest %.1f mm)\n", m.closest_to_target_mm);
  }
  if (m.path_efficiency > 0.0) {
    appendf(out, "path efficiency       %.2f (route %.1f mm)\n", m.path_efficiency, m.route_length_mm);
  } else {
    appendf(out, "path efficiency       n/a\n");
  }
  auto optional_figure = [&out](const char* name, const std::optional<double>& v, const char* unit) {
    if (v) {
      appendf(out, "%-21s %.2f %s\n", name, *v, unit);
    } else {
      appendf(out, "%-21s n/a\n", name);
    }
  };
  optional_figure("fluoroscopy time", m.fluoroscopy_time_s, "s");
  optional_figure("dose-area product", m.dose_area_product_mGy_cm2, "mGy cm2");
  if (m.fluoroscopy_runs) {
    appendf(out, "%-21s %d\n", "fluoroscopy runs", *m.fluoroscopy_runs);
  } else {
    appendf(out, "%-21s n/a\n", "fluoroscopy runs");
  }
  optional_figure("contrast volume", m.contrast_volume_ml, "ml");
  if (m.packing_density_pct) {  // a coiling case: its figures, else no lines at all
    optional_figure("packing density", m.packing_density_pct, "%");
    optional_figure("coil length deployed", m.coil_length_mm, "mm");
    const std::optional<double> hern = m.coil_herniations ? std::optional<double>(*m.coil_herniations) : std::nullopt;
    optional_figure("coil herniations", hern, "");
    if (m.coil_herniations > 0 && m.coil_herniated_peak_nodes && m.coil_herniated_depth_mm) {
      appendf(out, "%-21s up to %d nodes at once, %.2f mm past the neck plane\n", "herniation extent",
              *m.coil_herniated_peak_nodes, *m.coil_herniated_depth_mm);
    }
    optional_figure("kick-back", m.kick_back_mm, "mm");
    optional_figure("kick-forward", m.kick_forward_mm, "mm");
    format_detach_forces(out, m);
    if (m.coil_sleep_skipped_steps && m.coil_sleep_wakes) {
      appendf(out, "%-21s %lld coil steps skipped, %lld wakes\n", "coil sleep", static_cast<long long>(*m.coil_sleep_skipped_steps),
              static_cast<long long>(*m.coil_sleep_wakes));
    }
  }
  if (m.balloon_inflations) {  // an angioplasty case: its figures, else no lines at all
    optional_figure("stenosis before", m.stenosis_before_pct, "%");
    optional_figure("residual stenosis", m.residual_stenosis_pct, "%");
    optional_figure("balloon inflations", std::optional<double>(*m.balloon_inflations), "");
    optional_figure("balloon inflated", m.balloon_inflated_s, "s");
    const std::optional<double> risk = m.rupture_risk_events ? std::optional<double>(*m.rupture_risk_events) : std::nullopt;
    optional_figure("rupture-risk events", risk, "");
  }
  if (m.thrombectomy) format_thrombectomy(out, *m.thrombectomy);  // a thrombectomy case, else no lines at all
  if (const std::optional<double> pct = m.haptic_dropped_pct()) {  // a real-time run, else no line
    appendf(out, "%-21s %lld (%.2f %% of the run's real time)\n", "haptic ticks dropped",
            static_cast<long long>(*m.haptic_dropped_ticks), *pct);
  }
  return out;
}

std::vector<NamedMetric> named_metrics(const Metrics& m) {
  std::vector<NamedMetric> out;
  auto add = [&out](const char* name, double v) { out.push_back({name, v}); };
  // A figure the run has only in some cases (an optional): named when it has one.
  auto add_if = [&add](const char* name, const auto& v) {
    if (v) add(name, static_cast<double>(*v));
  };
  add("procedure_time_s", static_cast<double>(m.procedure_time_us) * 1e-6);
  if (m.has_target) {
    add("target_reached", m.target_reached ? 1.0 : 0.0);
    if (m.target_reached) add("time_to_target_s", static_cast<double>(m.time_to_target_us) * 1e-6);
    add("closest_to_target_mm", m.closest_to_target_mm);
  }
  add("tip_path_mm", m.tip_path_mm);
  if (m.path_efficiency > 0.0) add("path_efficiency", m.path_efficiency);
  add("wall_contacts", m.wall_contacts);
  add("peak_wall_force_mN", m.peak_wall_force_mN);
  add("time_above_threshold_s", static_cast<double>(m.time_above_threshold_us) * 1e-6);
  if (m.wrong_branch_entries >= 0) add("wrong_branch_entries", m.wrong_branch_entries);
  add("retractions", m.retractions);
  add("peak_insertion_speed_mm_s", m.peak_insertion_speed_mm_s);
  add("tool_changes", m.tool_changes);
  add("peak_hand_force_mN", m.peak_hand_force_mN);
  add("unconverged_pct", m.unconverged_pct_max());
  // Per tool, under its name (the server's results and debrief list them; criteria name the
  // largest, above).
  for (const ToolConvergence& c : m.convergence) out.push_back({"unconverged_pct." + c.tool, c.unconverged_pct()});
  add_if("fluoroscopy_time_s", m.fluoroscopy_time_s);
  add_if("dose_area_product_mGy_cm2", m.dose_area_product_mGy_cm2);
  add_if("fluoroscopy_runs", m.fluoroscopy_runs);
  add_if("contrast_volume_ml", m.contrast_volume_ml);
  add_if("packing_density_pct", m.packing_density_pct);
  add_if("coil_length_mm", m.coil_length_mm);
  add_if("coil_herniations", m.coil_herniations);
  add_if("coil_herniated_peak_nodes", m.coil_herniated_peak_nodes);
  add_if("coil_herniated_depth_mm", m.coil_herniated_depth_mm);
  add_if("kick_back_mm", m.kick_back_mm);
  add_if("kick_forward_mm", m.kick_forward_mm);
  add_if("coil_detach_force_peak_mN", m.coil_detach_force_peak_mN);
  add_if("coil_detached_under_tension", m.coil_detached_under_tension);
  add_if("coil_sleep_skipped_steps", m.coil_sleep_skipped_steps);
  add_if("coil_sleep_wakes", m.coil_sleep_wakes);
  add_if("stenosis_before_pct", m.stenosis_before_pct);
  add_if("residual_stenosis_pct", m.residual_stenosis_pct);
  add_if("balloon_inflations", m.balloon_inflations);
  add_if("balloon_inflated_s", m.balloon_inflated_s);
  add_if("rupture_risk_events", m.rupture_risk_events);
  if (m.thrombectomy) {  // eTICI as its ordinal: 0, 1, 2a = 2, 2b50 = 3, 2b67 = 4, 2c = 5, 3 = 6
    const ThrombectomyFigures& t = *m.thrombectomy;
    add("thrombectomy_passes", t.passes);
    const std::size_t graded = std::min<std::size_t>(static_cast<std::size_t>(t.passes), ThrombectomyFigures::kMaxPasses);
    for (std::size_t i = 0; i < graded; ++i) {
      out.push_back({"etici_pass_" + std::to_string(i + 1), static_cast<double>(t.etici_after_pass[i])});
    }
    add("etici_final", static_cast<double>(t.etici_final));
    add("reperfused_pct_final", t.reperfused_pct_final);
    add("first_pass_effect", t.first_pass_effect ? 1.0 : 0.0);
    add("emboli", t.emboli);
    add("emboli_new_territory", t.emboli_new_territory);
    add("emboli_in_transit", static_cast<double>(t.emboli_in_transit.size()));
    if (t.time_to_reperfusion_us >= 0) add("time_to_reperfusion_s", static_cast<double>(t.time_to_reperfusion_us) * 1e-6);
    add("balloon_guide_inflations", t.balloon_guide_inflations);
    add("flow_arrest_s", t.flow_arrest_s);
    if (t.stent_passes > 0) add("retrieval_force_peak_N", t.retrieval_force_peak_N);
  }
  add_if("haptic_dropped_ticks", m.haptic_dropped_ticks);
  return out;
}

std::vector<std::string> metric_names() {
  return {"procedure_time_s", "target_reached", "time_to_target_s", "closest_to_target_mm", "tip_path_mm",
          "path_efficiency", "wall_contacts", "peak_wall_force_mN", "time_above_threshold_s",
          "wrong_branch_entries", "retractions", "peak_insertion_speed_mm_s", "tool_changes",
          "peak_hand_force_mN", "unconverged_pct", "fluoroscopy_time_s", "dose_area_product_mGy_cm2", "fluoroscopy_runs",
          "contrast_volume_ml", "packing_density_pct", "coil_length_mm", "coil_herniations", "coil_herniated_peak_nodes",
          "coil_herniated_depth_mm", "kick_back_mm", "kick_forward_mm", "coil_detach_force_peak_mN", "coil_detached_under_tension",
          "coil_sleep_skipped_steps", "coil_sleep_wakes",
          "stenosis_before_pct", "residual_stenosis_pct", "balloon_inflations", "balloon_inflated_s",
          "rupture_risk_events", "thrombectomy_passes", "etici_pass_1", "etici_pass_2", "etici_pass_3", "etici_pass_4",
          "etici_pass_5", "etici_pass_6", "etici_pass_7", "etici_pass_8", "etici_final", "reperfused_pct_final",
          "first_pass_effect", "emboli", "emboli_new_territory", "emboli_in_transit", "time_to_reperfusion_s", "balloon_guide_inflations",
          "flow_arrest_s", "retrieval_force_peak_N", "haptic_dropped_ticks"};
}

}  // namespace cathbox::session
