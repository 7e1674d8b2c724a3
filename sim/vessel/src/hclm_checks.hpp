#pragma once
// What the HCLM reader (hclm.cpp) shares with the model checks (hclm_checks.cpp): the source
// lines of a segment block, the capped error list, and the cross-segment rules.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "vessel/diagnostic.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::vessel::detail {

inline constexpr std::size_t kMaxErrors = 100;

// Source lines of one segment block, for diagnostics of cross-segment rules.
struct SegmentLines {
  int g = 0;
  int p = 0;
  int c = 0;
  int n = 0;
};

class ErrorSink {
 public:
  ErrorSink(std::string_view file, std::vector<Diagnostic>& out) : file_(file), out_(out) {}
  void add(int line, std::string message) {
    if (out_.size() < kMaxErrors) out_.push_back({std::string(file_), line, std::move(message)});
  }
  [[nodiscard]] bool full() const { return out_.size() >= kMaxErrors; }

 private:
  std::string_view file_;
  std::vector<Diagnostic>& out_;
};

// Cross-segment rules shared by the reader and validate_model(). `lines` may be empty.
void validate_semantics(const VesselModel& model, const std::vector<SegmentLines>& lines, ErrorSink& sink);

}  // namespace cathbox::vessel::detail
