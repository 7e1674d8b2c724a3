#include "app/replay_panel.hpp"

#include <algorithm>
#include <array>
#include <filesystem>

#include <imgui.h>

namespace cathbox::app {
namespace {
constexpr std::array<double, 7> kSpeeds = {0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0};
}  // namespace

void ReplayPanel::rescan() {
  records_.clear();
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(records_dir_, ec)) {
    if (e.path().extension() == ".cbxrec") records_.push_back(e.path().string());
  }
  std::sort(records_.rbegin(), records_.rend());  // names start with the date: newest first
  scanned_ = true;
}

// Play or pause, the speed, the seek slider and where the replay is.
void ReplayPanel::draw_transport(session::ReplayPlayer& player, float width) {
  const double period_s = static_cast<double>(player.header().period_us) * 1e-6;
  if (ImGui::Button(player.playing() ? "pause" : "play ", ImVec2(60.0F, 0.0F))) {
    if (player.playing()) {
      player.pause();
    } else {
      if (player.position() >= player.total_ticks()) player.seek(0);
      player.play();
    }
  }
  ImGui::SameLine();
  ImGui::SetNextItemWidth(90.0F);
  char label[16];
  std::snprintf(label, sizeof label, "%gx", player.speed());
  if (ImGui::BeginCombo("speed", label)) {
    for (const double sp : kSpeeds) {
      std::snprintf(label, sizeof label, "%gx", sp);
      if (ImGui::Selectable(label, sp == player.speed())) player.set_speed(sp);
    }
    ImGui::EndCombo();
  }
  ImGui::SameLine();
  float at_s = static_cast<float>(static_cast<double>(player.target()) * period_s);
  const float total_s = static_cast<float>(static_cast<double>(player.total_ticks()) * period_s);
  ImGui::SetNextItemWidth(std::max(120.0F, width - 420.0F));
  if (ImGui::SliderFloat("##seek", &at_s, 0.0F, total_s, "%.2f s")) {
    player.seek(static_cast<std::int64_t>(static_cast<double>(at_s) / period_s));
  }
  ImGui::SameLine();
  ImGui::Text("%.2f / %.2f s%s", static_cast<double>(player.position()) * period_s, static_cast<double>(total_s),
              player.seeking() ? "  seeking..." : "");
}

// Whether the run replays as recorded (its state hashes), and what the record is.
void ReplayPanel::draw_checks(session::ReplayPlayer& player) {
  const session::ReplayHand& hand = player.replay().hand();
  if (hand.first_mismatch()) {
    ImGui::TextColored(ImVec4(1.0F, 0.4F, 0.3F, 1.0F), "state hash differs from tick %lld: this run does not replay as recorded",
                       static_cast<long long>(hand.first_mismatch()->tick));
  } else {
    ImGui::Text("state hashes match so far (%lld checked)", static_cast<long long>(hand.hashes_checked()));
  }
  if (!player.record_problem().empty()) ImGui::TextColored(ImVec4(1.0F, 0.8F, 0.3F, 1.0F), "%s", player.record_problem().c_str());
  ImGui::TextDisabled("%s  (%s, %s)", player.path().c_str(), player.header().case_name.c_str(),
                      player.header().hand_description.c_str());
}

// Another record to open, a rescan of the folder, or back to a live run.
void ReplayPanel::draw_records(session::ReplayPlayer& player, float width, ReplayPanelActions& act) {
  ImGui::SetNextItemWidth(std::min(480.0F, width - 200.0F));
  if (ImGui::BeginCombo("open", "another record...")) {
    for (const std::string& r : records_) {
      if (ImGui::Selectable(std::filesystem::path(r).filename().string().c_str(), r == player.path())) act.open = r;
    }
    ImGui::EndCombo();
  }
  ImGui::SameLine();
  if (ImGui::Button("rescan")) rescan();
  ImGui::SameLine();
  if (ImGui::Button("back to a live run")) act.back_to_live = true;
}

ReplayPanelActions ReplayPanel::draw(const Viewport& global, session::ReplayPlayer& player) {
  ReplayPanelActions act;
  if (!scanned_) rescan();
  constexpr ImGuiWindowFlags kFixed = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                      ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings;
  const float width = static_cast<float>(global.width) - 16.0F;
  ImGui::SetNextWindowPos(ImVec2(static_cast<float>(global.x) + 8.0F, static_cast<float>(global.y + global.height) - 8.0F),
                          ImGuiCond_Always, ImVec2(0.0F, 1.0F));
  ImGui::SetNextWindowSize(ImVec2(width, 0.0F));
  ImGui::SetNextWindowBgAlpha(0.8F);
  if (ImGui::Begin("Replay", nullptr, kFixed | ImGuiWindowFlags_AlwaysAutoResize)) {
    draw_transport(player, width);
    draw_checks(player);
    draw_records(player, width, act);
  }
  ImGui::End();
  return act;
}

}  // namespace cathbox::app
