#pragma once
// The case picker's content, without GL: for each case of the catalog its summary (title,
// description, anatomy; case_summary.hpp) and its thumbnail image (case_thumbnail.hpp), made
// the first time the picker is shown and again when the catalog changes (the server's
// assigned cases arrive). The panel (case_picker_panel.hpp) uploads the images and draws them.
#include <string>
#include <vector>

#include "app/case_catalog.hpp"
#include "app/case_summary.hpp"
#include "app/case_thumbnail.hpp"

namespace cathbox::app {

struct CasePickerEntry {
  CaseEntry file;
  CaseSummary summary;
  Image thumbnail;  // RGBA, kThumbnailSize_px square; the background alone when the case has no anatomy
};

class CasePickerModel {
 public:
  static constexpr int kThumbnailSize_px = 112;

  // Summarises the catalog's cases unless they are the ones already held; true when it did.
  bool refresh(const CaseCatalog& catalog);
  [[nodiscard]] const std::vector<CasePickerEntry>& entries() const { return entries_; }

 private:
  std::vector<CasePickerEntry> entries_;
};

}  // namespace cathbox::app
