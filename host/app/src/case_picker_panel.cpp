#include "app/case_picker_panel.hpp"

#include <algorithm>
#include <cstdint>

#include <imgui.h>

#include "app/gl.hpp"

namespace cathbox::app {
namespace {
constexpr float kThumb_px = static_cast<float>(CasePickerModel::kThumbnailSize_px);
constexpr float kMargin_px = 24.0F;
}  // namespace

CasePickerPanel::~CasePickerPanel() { release_textures(); }

void CasePickerPanel::release_textures() {
  if (!textures_.empty()) glDeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
  textures_.clear();
}

void CasePickerPanel::upload_thumbnails() {
  release_textures();
  textures_.resize(model_.entries().size());
  if (textures_.empty()) return;
  glGenTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  for (std::size_t i = 0; i < textures_.size(); ++i) {
    const Image& img = model_.entries()[i].thumbnail;
    glBindTexture(GL_TEXTURE_2D, textures_[i]);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, img.width, img.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, img.pixels.data());
  }
  glBindTexture(GL_TEXTURE_2D, 0);
}

int CasePickerPanel::draw(const Viewport& area, const CaseCatalog& catalog, int current_case) {
  if (!open_) return -1;
  if (model_.refresh(catalog) || textures_.size() != model_.entries().size()) upload_thumbnails();
  const float w = std::max(320.0F, static_cast<float>(area.width) - 2.0F * kMargin_px);
  const float h = std::max(240.0F, static_cast<float>(area.height) - 2.0F * kMargin_px);
  ImGui::SetNextWindowPos(ImVec2(static_cast<float>(area.x) + kMargin_px, static_cast<float>(area.y) + kMargin_px));
  ImGui::SetNextWindowSize(ImVec2(w, h));
  int picked = -1;
  if (ImGui::Begin("Cases", &open_, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                                        ImGuiWindowFlags_NoSavedSettings)) {
    const std::vector<CasePickerEntry>& rows = model_.entries();
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const CasePickerEntry& e = rows[i];
      ImGui::PushID(static_cast<int>(i));
      const ImVec2 top = ImGui::GetCursorPos();
      // The whole row is the button; the thumbnail and the text are drawn over it.
      if (ImGui::Selectable("##row", static_cast<int>(i) == current_case, ImGuiSelectableFlags_AllowItemOverlap,
                            ImVec2(0.0F, kThumb_px + 4.0F))) {
        picked = static_cast<int>(i);
      }
      if (scroll_to_current_ && static_cast<int>(i) == current_case) ImGui::SetScrollHereY(0.0F);
      ImGui::SetCursorPos(ImVec2(top.x + 2.0F, top.y + 2.0F));
      ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(textures_[i])), ImVec2(kThumb_px, kThumb_px));
      ImGui::SameLine();
      ImGui::BeginGroup();
      ImGui::TextUnformatted(e.summary.title.c_str());
      ImGui::TextDisabled("%s", e.file.name.c_str());
      ImGui::PushTextWrapPos(0.0F);
      if (!e.summary.error.empty()) ImGui::TextColored(ImVec4(1.0F, 0.5F, 0.4F, 1.0F), "%s", e.summary.error.c_str());
      ImGui::TextUnformatted(e.summary.description.c_str());
      ImGui::PopTextWrapPos();
      ImGui::EndGroup();  // the cursor is now below the taller of the thumbnail and the text
      ImGui::Separator();
      ImGui::PopID();
    }
  }
  ImGui::End();
  scroll_to_current_ = false;
  if (picked >= 0) open_ = false;
  return picked;
}

}  // namespace cathbox::app
