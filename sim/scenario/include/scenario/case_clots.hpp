#pragma once
// A case's `clot` statements against its vessel model: the flow module's clots (segment
// indices, checked extents), or one line "file:line: clot: ..." naming the statement.
#include <vector>

#include "base/result.hpp"
#include "flow/clot.hpp"
#include "scenario/case_file.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::tool {

[[nodiscard]] base::Result<std::vector<flow::Clot>> resolve_clots(const Case& c, const vessel::VesselModel& model);

}  // namespace cathbox::tool
