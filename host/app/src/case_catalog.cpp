#include "app/case_catalog.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>

namespace cathbox::app {

namespace {

// The case files (`.case`) one folder down, as "SUB/NAME.case": a subfolder's vessel files are
// its cases' own, not cases of their own.
void scan_subfolder(const std::filesystem::path& sub, std::vector<CaseEntry>& out) {
  std::error_code ec;
  std::filesystem::directory_iterator it(sub, ec);
  if (ec) return;
  for (const auto& e : it) {
    if (!e.is_regular_file(ec) || e.path().extension() != ".case") continue;
    out.push_back({(sub.filename() / e.path().filename()).string(), e.path().string()});
  }
}

}  // namespace

base::Result<CaseCatalog> CaseCatalog::scan(const std::string& dir, std::span<const std::string> extensions) {
  CaseCatalog c;
  std::error_code ec;
  std::filesystem::directory_iterator it(dir, ec);
  if (ec) return base::Error{dir + ": " + ec.message()};
  for (const auto& e : it) {
    if (e.is_directory(ec)) {
      scan_subfolder(e.path(), c.entries_);
      continue;
    }
    if (!e.is_regular_file(ec)) continue;
    const std::string ext = e.path().extension().string();
    if (std::find(extensions.begin(), extensions.end(), ext) == extensions.end()) continue;
    c.entries_.push_back({e.path().filename().string(), e.path().string()});
  }
  std::sort(c.entries_.begin(), c.entries_.end(),
            [](const CaseEntry& a, const CaseEntry& b) { return a.name < b.name; });
  return c;
}

void CaseCatalog::prepend(std::vector<CaseEntry> first) {
  first.insert(first.end(), entries_.begin(), entries_.end());
  entries_ = std::move(first);
}

int CaseCatalog::index_of_path(const std::string& path) const {
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    if (entries_[i].path == path) return static_cast<int>(i);
  }
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    std::error_code ec;
    if (std::filesystem::equivalent(entries_[i].path, path, ec)) return static_cast<int>(i);
  }
  return -1;
}

int CaseCatalog::default_index(const std::string& preferred, const std::string& preferred_extension) const {
  if (entries_.empty()) return -1;
  int fallback = -1;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    if (entries_[i].name.find(preferred) == std::string::npos) continue;
    if (std::filesystem::path(entries_[i].name).extension() == preferred_extension) return static_cast<int>(i);
    if (fallback < 0) fallback = static_cast<int>(i);
  }
  return fallback >= 0 ? fallback : 0;
}

}  // namespace cathbox::app
