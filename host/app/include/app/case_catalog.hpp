#pragma once
// The case picker's list: the case files in a folder (by extension) and the `.case` files of its
// subfolders (named "SUB/NAME.case"), sorted by name, with the
// default case (the first whose name contains `preferred`, one with `preferred_extension`
// first; else the first of all).
#include <span>
#include <string>
#include <vector>

#include "base/result.hpp"

namespace cathbox::app {

struct CaseEntry {
  std::string name;  // file name without the folder ("SUB/NAME.case" one folder down)
  std::string path;
};

class CaseCatalog {
 public:
  // Lists `dir`; or one line naming an unreadable folder.
  [[nodiscard]] static base::Result<CaseCatalog> scan(const std::string& dir, std::span<const std::string> extensions);

  [[nodiscard]] const std::vector<CaseEntry>& entries() const { return entries_; }
  // Puts `first` before the scanned entries (the server's assigned cases).
  void prepend(std::vector<CaseEntry> first);
  // Index of the entry at `path` (the same string, else the same file), or -1.
  [[nodiscard]] int index_of_path(const std::string& path) const;
  // Index of the default case, or -1 when the catalog is empty.
  [[nodiscard]] int default_index(const std::string& preferred, const std::string& preferred_extension = "") const;

 private:
  std::vector<CaseEntry> entries_;
};

}  // namespace cathbox::app
