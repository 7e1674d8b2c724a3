#include "scenario/case_file.hpp"

#include <algorithm>

#include "base/read_file.hpp"
#include "case_parser.hpp"

namespace cathbox::tool {
namespace {

constexpr std::size_t kMaxCaseBytes = 16u << 20;

}  // namespace

CaseParse parse_case(std::string_view text, std::string_view file_name) {
  return detail::CaseParser(text, file_name).run();
}

CaseParse load_case(const std::string& path) {
  const base::Result<std::string, base::ReadFileError> text = base::read_file(path, kMaxCaseBytes);
  if (!text) return base::Error{path + ":0: cannot read the file (missing, unreadable or larger than 16 MiB)"};
  return parse_case(*text, path);
}

void steer_aspiration_catheters(Case& c) {
  for (ToolSpec& t : c.tools) {
    const bool aspirated = std::any_of(c.aspiration.begin(), c.aspiration.end(), [&t](const CaseAspiration& a) { return a.tool == t.name; });
    t.steered_by_inner = aspirated ? InnerSteering::kWhileAdvanced : InnerSteering::kNone;
  }
}

}  // namespace cathbox::tool
