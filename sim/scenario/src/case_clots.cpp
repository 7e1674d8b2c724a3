#include "scenario/case_clots.hpp"

#include <string>

#include "base/text_lines.hpp"
#include "flow/centerline_locator.hpp"

namespace cathbox::tool {

base::Result<std::vector<flow::Clot>> resolve_clots(const Case& c, const vessel::VesselModel& model) {
  std::vector<flow::Clot> clots;
  if (c.clots.empty()) return clots;
  const flow::CenterlineLocator locator(model);
  for (const CaseClot& k : c.clots) {
    const auto fail = [&](const std::string& message) { return base::Error{base::text::located(c.flow.source, k.line, "clot: " + message)}; };
    const std::optional<std::size_t> index = model.index_of(k.segment_id);
    if (!index) return fail("no segment " + std::to_string(k.segment_id) + " in the vessel model");
    const auto i = static_cast<std::uint32_t>(*index);
    const double length = locator.length_mm(i);
    if (k.from_mm + k.length_mm > length + 1e-9) {
      return fail("runs past the end of segment " + std::to_string(k.segment_id) + " (" + std::to_string(length) + " mm long)");
    }
    for (const flow::Clot& other : clots) {
      if (other.segment == i && other.arc_start_mm < k.from_mm + k.length_mm && k.from_mm < other.arc_start_mm + other.length_mm) {
        return fail("overlaps another clot in segment " + std::to_string(k.segment_id));
      }
    }
    clots.push_back(flow::Clot{i, k.from_mm, k.length_mm, k.composition, k.open_fraction});
  }
  return clots;
}

}  // namespace cathbox::tool
