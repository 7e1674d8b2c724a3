#pragma once
// The trainer's case picker (Dear ImGui): a window over the global view listing every case of
// the catalog as a row: its anatomy thumbnail (AP projection of the centreline tubes, the
// target ringed), its title and file, and its description; a click opens the case. It opens
// scrolled to the current case. The rows
// come from CasePickerModel (no GL); this class owns their GL textures.
#include <vector>

#include "app/case_picker_model.hpp"
#include "app/viewport.hpp"

namespace cathbox::app {

class CasePickerPanel {
 public:
  CasePickerPanel() = default;
  ~CasePickerPanel();
  CasePickerPanel(const CasePickerPanel&) = delete;
  CasePickerPanel& operator=(const CasePickerPanel&) = delete;

  // Opens the window, scrolled to the current case.
  void open() {
    open_ = true;
    scroll_to_current_ = true;
  }
  [[nodiscard]] bool is_open() const { return open_; }
  // Draws the window over `area` while open (needs the GL context current, inside an ImGui
  // frame); the index of the case picked this frame (the window then closes), else -1.
  [[nodiscard]] int draw(const Viewport& area, const CaseCatalog& catalog, int current_case);
  [[nodiscard]] const CasePickerModel& model() const { return model_; }

 private:
  void upload_thumbnails();
  void release_textures();

  CasePickerModel model_;
  std::vector<unsigned> textures_;  // one per model entry
  bool open_ = false;
  bool scroll_to_current_ = false;
};

}  // namespace cathbox::app
