#include "app/case_picker_model.hpp"

#include <algorithm>

namespace cathbox::app {

bool CasePickerModel::refresh(const CaseCatalog& catalog) {
  const std::vector<CaseEntry>& files = catalog.entries();
  const bool same = files.size() == entries_.size() &&
                    std::equal(files.begin(), files.end(), entries_.begin(),
                               [](const CaseEntry& f, const CasePickerEntry& e) { return f.path == e.file.path; });
  if (same) return false;
  entries_.clear();
  entries_.reserve(files.size());
  for (const CaseEntry& f : files) {
    CasePickerEntry e{f, read_case_summary(f.path), {}};
    e.thumbnail = render_thumbnail(e.summary.tubes, e.summary.target_mm, kThumbnailSize_px).image;
    entries_.push_back(std::move(e));
  }
  return true;
}

}  // namespace cathbox::app
