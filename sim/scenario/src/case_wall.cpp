#include "scenario/case_wall.hpp"

#include "tool/arterial_wall.hpp"
#include "tool/compliant_contact.hpp"

namespace cathbox::tool {

void use_case_wall(Simulator& sim, const CaseWall* wall) {
  if (wall == nullptr) return;
  use_compliant_contact(sim, compliant_contact(WallShell(arterial_wall(wall->territory), wall->radius_mm)));
}

}  // namespace cathbox::tool
