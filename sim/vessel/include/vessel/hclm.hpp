#pragma once
// Reading and writing HCLM files (thesis Appendix A), the text form of the central axis model.
//
//   s <segment count>
//   g <id>                    starts a segment block
//   l <name>                  optional, rest of the line
//   f <flow>                  optional
//   p <count> <id>...         parents
//   c <count> <id>...         children
//   n <point count>
//   v <x> <y> <z> <radius>    exactly n lines, millimetres
//
// Blank lines, extra spaces/tabs and CRLF line ends are accepted. Every problem is reported as
// one Diagnostic naming the file and line; the reader never throws and never allocates more
// than the input's size justifies. Writing then reading gives back an identical model.
#include <string>
#include <string_view>
#include <vector>

#include "vessel/diagnostic.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::vessel {

struct HclmReadResult {
  VesselModel model;                   // meaningful only when ok()
  std::vector<Diagnostic> errors;      // every problem found, in the order found (capped at 100)
  [[nodiscard]] bool ok() const { return errors.empty(); }
};

// Parses and validates HCLM text. `file_name` is only used in diagnostics.
[[nodiscard]] HclmReadResult read_hclm(std::string_view text, std::string_view file_name = "<text>");
// Reads a file from disk (a missing or unreadable file is one diagnostic with line 0).
[[nodiscard]] HclmReadResult load_hclm(const std::string& path);

// Checks a model built in memory by the same rules as the reader (ids, lists, numbers).
[[nodiscard]] std::vector<Diagnostic> validate_model(const VesselModel& model,
                                                     std::string_view file_name = "<model>");

// Canonical HCLM text (numbers in shortest round-trip form, LF line ends).
[[nodiscard]] std::string write_hclm(const VesselModel& model);
// Writes the file; returns an empty string on success, else the error.
[[nodiscard]] std::string save_hclm(const VesselModel& model, const std::string& path);

}  // namespace cathbox::vessel
