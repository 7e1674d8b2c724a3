#pragma once
// A case's `wall TERRITORY [RADIUS_MM]` line made the simulator's contact
// (tool/compliant_contact.hpp) and the wall the pulse moves (tool/wall_distension.hpp): the same
// laws for a wall meshed from the centrelines and for a case's own `surface`.
#include <memory>

#include "scenario/case_file.hpp"
#include "tool/displaced_wall.hpp"
#include "tool/simulator.hpp"
#include "tool/wall_distension.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::tool {

// The line's radius, else `model`'s (its centreline graph's median radius: the distance to the
// surface for an imported lumen); 0 when neither gives one.
[[nodiscard]] double case_wall_radius_mm(const CaseWall& wall, const vessel::VesselModel* model);

// Null (no `wall` line): the rigid wall, nothing changes. Call once, after construction.
// `model`: the vessel as read (CaseWorld::source_model()), for a line without a radius.
void use_case_wall(Simulator& sim, const CaseWall* wall, const vessel::VesselModel* model = nullptr);

// The compliant wall as the tools meet it: the world's exact wall (mesh or surface, never refit)
// moved along its normals by every segment's Laplace distension under the pressure set last.
class CaseWallField {
 public:
  CaseWallField(const WallModel& inner, const vessel::VesselModel& model, const ArterialWall& wall)
      : displaced_(inner), distension_(model, wall) {
    distension_.apply(0.0, displaced_);  // sizes the field: set_pressure_kPa allocates nothing
  }
  [[nodiscard]] const WallModel& wall() const { return displaced_; }
  [[nodiscard]] const WallDistension& distension() const { return distension_; }
  [[nodiscard]] double pressure_kPa() const { return pressure_kPa_; }
  // The transmural pressure over the one the wall was imaged (or meshed) at; haptic-loop safe.
  void set_pressure_kPa(double pressure_kPa) {
    pressure_kPa_ = pressure_kPa;
    distension_.apply(pressure_kPa, displaced_);
  }

 private:
  DisplacedWall displaced_;
  WallDistension distension_;
  double pressure_kPa_ = 0.0;
};

// The field for a case with a `wall` line and a vessel model (null otherwise: tubes keep the
// contact alone). `inner` must outlive it.
[[nodiscard]] std::unique_ptr<CaseWallField> make_case_wall_field(const CaseWall* wall, const WallModel& inner,
                                                                  const vessel::VesselModel* model);

}  // namespace cathbox::tool
