#include "scenario/case_wall.hpp"

#include "tool/arterial_wall.hpp"
#include "tool/compliant_contact.hpp"

namespace cathbox::tool {

double case_wall_radius_mm(const CaseWall& wall, const vessel::VesselModel* model) {
  if (wall.radius_mm > 0.0) return wall.radius_mm;
  return model != nullptr ? median_radius_mm(*model) : 0.0;
}

void use_case_wall(Simulator& sim, const CaseWall* wall, const vessel::VesselModel* model) {
  if (wall == nullptr) return;
  const double radius_mm = case_wall_radius_mm(*wall, model);
  if (!(radius_mm > 0.0)) return;  // the parser asks a vessel of a line without a radius
  use_compliant_contact(sim, compliant_contact(WallShell(arterial_wall(wall->territory), radius_mm)));
}

std::unique_ptr<CaseWallField> make_case_wall_field(const CaseWall* wall, const WallModel& inner,
                                                    const vessel::VesselModel* model) {
  if (wall == nullptr || model == nullptr || model->segments.empty()) return nullptr;
  return std::make_unique<CaseWallField>(inner, *model, arterial_wall(wall->territory));
}

}  // namespace cathbox::tool
