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
  const auto aspirated = [&c](const std::string& name) {
    return std::any_of(c.aspiration.begin(), c.aspiration.end(), [&name](const CaseAspiration& a) { return a.tool == name; });
  };
  for (ToolSpec& t : c.tools) t.steered_by_inner = aspirated(t.name) ? InnerSteering::kWhileAdvanced : InnerSteering::kNone;
  // A catheter run in an aspiration catheter (the ADAPT and Solumbra stacks' microcatheter) is
  // steered by the wire it carries while advanced too: unsteered, only predicted along the wire's
  // path, the ADAPT stack's converged steps left the wire for the PCom (convergence.md, "An
  // aspiration stack sub-stepped"), and the M1 Solumbra stack's left it at the M1's junction once
  // the lumen's bending push was the moment's change ("The lumen's bending push from the change
  // of the moment").
  for (ToolSpec& t : c.tools) {
    if (t.kind != ToolKind::kCatheter || t.inside.empty() || !aspirated(t.inside)) continue;
    t.steered_by_inner = InnerSteering::kWhileAdvanced;
  }
}

}  // namespace cathbox::tool
