#pragma once
// A case's `wall TERRITORY RADIUS_MM` line made the simulator's contact (tool/compliant_contact.hpp).
#include "scenario/case_file.hpp"
#include "tool/simulator.hpp"

namespace cathbox::tool {

// Null (no `wall` line): the rigid wall, nothing changes. Call once, after construction.
void use_case_wall(Simulator& sim, const CaseWall* wall);

}  // namespace cathbox::tool
