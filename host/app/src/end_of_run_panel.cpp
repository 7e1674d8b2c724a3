#include "app/end_of_run_panel.hpp"

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <string>

namespace cathbox::app {
namespace {

void optional_row(const char* name, const std::optional<double>& v, const char* unit) {
  if (v) {
    ImGui::Text("%-22s %8.2f %s", name, *v, unit);
  } else {
    ImGui::Text("%-22s      n/a", name);
  }
}

// A thrombectomy case: passes and the reperfusion graded after each; the balloon guide's flow arrest.
void draw_thrombectomy(const session::ThrombectomyFigures& t) {
  ImGui::Separator();
  ImGui::Text("%-22s %8d", "passes", t.passes);
  for (std::size_t i = 0; i < std::min<std::size_t>(static_cast<std::size_t>(t.passes), session::ThrombectomyFigures::kMaxPasses); ++i) {
    ImGui::Text("eTICI after pass %-5zu %8s (%.0f %%)", i + 1, std::string(flow::etici_label(t.etici_after_pass[i])).c_str(),
                t.reperfused_pct_after_pass[i]);
  }
  ImGui::Text("%-22s %8s (%.0f %%)", "eTICI final", std::string(flow::etici_label(t.etici_final)).c_str(), t.reperfused_pct_final);
  ImGui::Text("%-22s %8s", "first-pass effect", t.first_pass_effect ? "yes" : "no");
  ImGui::Text("%-22s %8d (%d new territory)", "emboli", t.emboli, t.emboli_new_territory);
  for (const std::string& where : t.emboli_lodged) ImGui::TextDisabled("  lodged in %s", where.c_str());
  for (const session::EmbolusInTransit& e : t.emboli_in_transit) {
    ImGui::TextDisabled("  in transit in %s, would lodge in %s%s", e.at.c_str(), e.would_lodge.empty() ? "(no flow)" : e.would_lodge.c_str(),
                        e.new_territory ? " (new territory)" : "");
  }
  if (t.time_to_reperfusion_us >= 0) {
    ImGui::Text("%-22s %8.2f s", "time to reperfusion", static_cast<double>(t.time_to_reperfusion_us) * 1e-6);
  } else {
    ImGui::Text("%-22s      n/a", "time to reperfusion");
  }
  ImGui::Text("%-22s %8d", "guide inflations", t.balloon_guide_inflations);
  ImGui::Text("%-22s %8.2f s", "flow arrest", t.flow_arrest_s);
  if (t.stent_passes > 0) ImGui::Text("%-22s %8.3f N", "retrieval force", t.retrieval_force_peak_N);
}

// Figures of the simulation and the rig, not of the trainee (greyed): the solver's share of steps
// that ran out of iterations, per tool (forces of those steps are not read); released coils at
// rest, not solved; a real-time run's dropped haptic ticks (did the rig keep up?).
void draw_simulation_figures(const session::Metrics& m) {
  for (const session::ToolConvergence& c : m.convergence) {
    if (c.solved_ticks > 0) ImGui::TextDisabled("%-22s %8.2f %% (%s)", "unconverged steps", c.unconverged_pct(), c.tool.c_str());
  }
  if (m.coil_sleep_skipped_steps && m.coil_sleep_wakes) {
    ImGui::TextDisabled("%-22s %8lld (%lld wakes)", "coil steps asleep", static_cast<long long>(*m.coil_sleep_skipped_steps),
                        static_cast<long long>(*m.coil_sleep_wakes));
  }
  if (const std::optional<double> pct = m.haptic_dropped_pct()) {
    ImGui::TextDisabled("%-22s %8lld (%.2f %% of real time)", "haptic ticks dropped", static_cast<long long>(*m.haptic_dropped_ticks),
                        *pct);
  }
}

}  // namespace

EndOfRunActions draw_end_of_run(const Viewport& area, const session::Metrics& m, const std::string& record_path,
                                bool replaying) {
  EndOfRunActions act;
  constexpr ImGuiWindowFlags kFixed = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                                      ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_AlwaysAutoResize;
  ImGui::SetNextWindowPos(ImVec2(static_cast<float>(area.x + area.width / 2), static_cast<float>(area.y + area.height / 2)),
                          ImGuiCond_Always, ImVec2(0.5F, 0.5F));
  if (ImGui::Begin(replaying ? "End of the recorded run" : "End of run", nullptr, kFixed)) {
    if (!m.has_target) {
      ImGui::Text("No target in this case");
    } else if (m.target_reached) {
      ImGui::Text("Target reached at %.2f s", static_cast<double>(m.time_to_target_us) * 1e-6);
    } else {
      ImGui::Text("Target not reached (closest %.1f mm)", m.closest_to_target_mm);
    }
    ImGui::Separator();
    ImGui::Text("%-22s %8.2f s", "procedure time", static_cast<double>(m.procedure_time_us) * 1e-6);
    ImGui::Text("%-22s %8.1f mm", "tip path length", m.tip_path_mm);
    if (m.path_efficiency > 0.0) {
      ImGui::Text("%-22s %8.2f (route %.0f mm)", "path efficiency", m.path_efficiency, m.route_length_mm);
    } else {
      ImGui::Text("%-22s      n/a", "path efficiency");
    }
    ImGui::Text("%-22s %8d", "wall contacts", m.wall_contacts);
    ImGui::Text("%-22s %8.1f mN", "peak wall force", m.peak_wall_force_mN);
    char above[32];
    std::snprintf(above, sizeof above, "time above %.0f mN", m.wall_force_threshold_mN);
    ImGui::Text("%-22s %8.2f s", above, static_cast<double>(m.time_above_threshold_us) * 1e-6);
    if (m.wrong_branch_entries >= 0) {
      ImGui::Text("%-22s %8d", "wrong-branch entries", m.wrong_branch_entries);
    } else {
      ImGui::Text("%-22s      n/a", "wrong-branch entries");
    }
    ImGui::Text("%-22s %8d", "retractions", m.retractions);
    ImGui::Text("%-22s %8.1f mm/s", "peak insertion speed", m.peak_insertion_speed_mm_s);
    ImGui::Text("%-22s %8d", "tool changes", m.tool_changes);
    ImGui::Text("%-22s %8.1f mN", "peak hand force", m.peak_hand_force_mN);
    draw_simulation_figures(m);
    ImGui::Separator();
    optional_row("fluoroscopy time", m.fluoroscopy_time_s, "s");
    optional_row("dose-area product", m.dose_area_product_mGy_cm2, "mGy cm2");
    if (m.fluoroscopy_runs) {
      ImGui::Text("%-22s %8d", "fluoroscopy runs", *m.fluoroscopy_runs);
    } else {
      ImGui::Text("%-22s      n/a", "fluoroscopy runs");
    }
    optional_row("contrast volume", m.contrast_volume_ml, "ml");
    if (m.thrombectomy) draw_thrombectomy(*m.thrombectomy);
    if (!record_path.empty()) {
      ImGui::Separator();
      ImGui::TextDisabled("record: %s", record_path.c_str());
    }
    if (!replaying) {
      if (ImGui::Button("again")) act.again = true;
      if (!record_path.empty()) {
        ImGui::SameLine();
        if (ImGui::Button("replay this run")) act.replay = true;
      }
    }
  }
  ImGui::End();
  return act;
}

}  // namespace cathbox::app
