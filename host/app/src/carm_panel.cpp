#include "app/carm_panel.hpp"

#include <cstdio>
#include <optional>

#include <imgui.h>

namespace cathbox::app {

namespace {

// A control the trainee asked for, sent only while they drive the unit.
struct Post {
  CArmPanelActions& act;
  bool driving;
  void operator()(std::optional<session::Control> c) const {
    if (c && driving) act.controls.push_back(*c);
  }
};

// Angles, and the projections that set them.
void draw_angles(CArmPanelModel& model, float field, const Post& post) {
  const flow::CArmPose& pose = model.pose();
  float lao = static_cast<float>(pose.lao_deg);
  float cranial = static_cast<float>(pose.cranial_deg);
  ImGui::SetNextItemWidth(field);
  const bool a1 = ImGui::SliderFloat("LAO+ / RAO-", &lao, -120.0F, 120.0F, "%.0f deg");
  ImGui::SetNextItemWidth(field);
  const bool a2 = ImGui::SliderFloat("cranial+ / caudal-", &cranial, -60.0F, 60.0F, "%.0f deg");
  if (a1 || a2) post(model.set_angles(lao, cranial));
  ImGui::SetNextItemWidth(field);
  if (ImGui::BeginCombo("projection", "pick...")) {
    for (std::size_t i = 0; i < model.projections().size(); ++i) {
      const flow::NamedProjection& p = model.projections()[i];
      char label[96];
      std::snprintf(label, sizeof label, "%s (%+.0f, %+.0f)", p.name.c_str(), p.lao_deg, p.cranial_deg);
      if (ImGui::Selectable(label, p.lao_deg == pose.lao_deg && p.cranial_deg == pose.cranial_deg)) post(model.pick_projection(i));
    }
    ImGui::EndCombo();
  }
}

// Geometry: source-image distance, table height, field of view, collimation; the pulse rate.
void draw_geometry(CArmPanelModel& model, float field, const Post& post) {
  const flow::CArmPose& pose = model.pose();
  float sid = static_cast<float>(pose.sid_mm);
  float table = static_cast<float>(pose.table_height_mm);
  float fov = static_cast<float>(pose.fov_mm);
  float collimation = static_cast<float>(pose.collimation);
  ImGui::SetNextItemWidth(field);
  bool g = ImGui::SliderFloat("SID", &sid, 800.0F, 1300.0F, "%.0f mm");
  ImGui::SetNextItemWidth(field);
  g = ImGui::SliderFloat("table height", &table, -200.0F, 200.0F, "%.0f mm") || g;
  ImGui::SameLine();
  const flow::CArm carm(pose);
  ImGui::TextDisabled("x%.2f", carm.magnification(carm.isocenter_mm()));
  ImGui::SetNextItemWidth(field);
  g = ImGui::SliderFloat("field of view", &fov, 100.0F, 420.0F, "%.0f mm") || g;
  ImGui::SetNextItemWidth(field);
  g = ImGui::SliderFloat("collimation", &collimation, 0.11F, 1.0F, "%.2f") || g;
  if (g) post(model.set_geometry(sid, table, fov, collimation));
  ImGui::TextUnformatted("pulses/s");
  for (const double rate : CArmPanelModel::kPulseRates) {
    ImGui::SameLine();
    char label[16];
    std::snprintf(label, sizeof label, "%g", rate);
    if (ImGui::RadioButton(label, model.pulse_rate_hz() == rate)) post(model.set_pulse_rate(rate));
  }
}

// Injection (the button and the I key) and the roadmap.
void draw_injection(CArmPanelModel& model, const Post& post, CArmPanelActions& act) {
  InjectionSettings inj = model.injection();
  float v = static_cast<float>(inj.volume_ml);
  float r = static_cast<float>(inj.rate_ml_s);
  float c = static_cast<float>(inj.concentration_mgI_ml);
  const float third = ImGui::GetContentRegionAvail().x / 3.0F - 6.0F;
  ImGui::SetNextItemWidth(third);
  bool i = ImGui::SliderFloat("##volume", &v, static_cast<float>(CArmPanelModel::kMinVolume_ml),
                              static_cast<float>(CArmPanelModel::kMaxVolume_ml), "%.1f mL");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(third);
  i = ImGui::SliderFloat("##rate", &r, static_cast<float>(CArmPanelModel::kMinRate_ml_s),
                         static_cast<float>(CArmPanelModel::kMaxRate_ml_s), "%.1f mL/s") || i;
  ImGui::SameLine();
  ImGui::SetNextItemWidth(third);
  i = ImGui::SliderFloat("##concentration", &c, static_cast<float>(CArmPanelModel::kMinConcentration_mgI_ml),
                         static_cast<float>(CArmPanelModel::kMaxConcentration_mgI_ml), "%.0f mgI/mL") || i;
  if (i) act.injection_changed = model.set_injection({v, r, c});
  if (ImGui::Button("Inject (I)")) post(model.inject());
  ImGui::SameLine();
  if (ImGui::Button("roadmap (R)")) post(CArmPanelModel::capture_roadmap());
  ImGui::SameLine();
  if (ImGui::Button("clear (X)")) post(CArmPanelModel::clear_roadmap());
}

}  // namespace

CArmPanelActions draw_carm_panel(const Viewport& area, CArmPanelModel& model, const session::FluoroView& unit, bool driving) {
  CArmPanelActions act;
  // The fields follow the unit unless the trainee is dragging one of them.
  if (!ImGui::IsAnyItemActive()) model.sync(unit.pose, unit.pulse_rate_hz);
  const Post post{act, driving};
  constexpr ImGuiWindowFlags kFixed = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                      ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings;
  ImGui::SetNextWindowPos(ImVec2(static_cast<float>(area.x), static_cast<float>(area.y)));
  ImGui::SetNextWindowSize(ImVec2(static_cast<float>(area.width), static_cast<float>(area.height)));
  if (ImGui::Begin("C-arm", nullptr, kFixed)) {
    if (!driving) ImGui::BeginDisabled();
    const float field = ImGui::GetContentRegionAvail().x * 0.5F;
    draw_angles(model, field, post);
    draw_geometry(model, field, post);
    ImGui::Separator();
    draw_injection(model, post, act);
    if (!driving) ImGui::EndDisabled();
    ImGui::Separator();
    ImGui::Text("%s  %.1f s  DAP %.2f mGy cm2  runs %d  contrast %.1f mL", unit.image.beam_on ? "X-RAY" : "pedal up",
                unit.exposure.fluoro_time_s, unit.exposure.dap_Gy_cm2 * 1e3, unit.exposure.runs, unit.contrast_ml);
    if (!model.error().empty()) ImGui::TextColored(ImVec4(1.0F, 0.5F, 0.3F, 1.0F), "%s", model.error().c_str());
  }
  ImGui::End();
  return act;
}

}  // namespace cathbox::app
