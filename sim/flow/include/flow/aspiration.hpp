#pragma once
// Aspiration thrombectomy: the vacuum at a catheter's tip, the force it puts on a clot, and what
// becomes of the clot (ingested, corked in the tip, or lost).
//
// - Vacuum (Froehler, J NeuroIntervent Surg 2017, measured at the pump / syringe): Penumbra
//   pump -25.6 inHg, 60 mL locking syringe -27.0 inHg. Force on a clot sealing the tip =
//   |pressure| x lumen area (pi ID^2 / 4).
// - Ingestion: to enter the lumen the clot is compressed radially from its diameter to the
//   catheter's inner diameter, strain e = 1 - ID / d, and slides in against its kinetic friction
//   on the catheter wall under that compression: the vacuum force must exceed
//   mu_k * sigma(e) * pi * ID * L (sigma: the clot's compression law). Else the clot corks the
//   tip (a clot narrower than the tip is always ingested).
// - Corked withdrawal: the grip (the vacuum force) must exceed what holds the clot: its static
//   wall friction under its wedge strain (kWedgeStrain: a lodged clot is ~10 % wider than its
//   unloaded lumen) plus the pressure difference across it (from the flow model: the
//   FlowNetwork's node pressures at the occluded segment's ends, lower under a balloon guide's
//   flow arrest) on the lumen area. Else the clot is lost (stays, or strips off the tip).
#include <cstdint>
#include <string_view>

#include "flow/clot_material.hpp"

namespace cathbox::flow {

enum class VacuumSource : std::uint8_t { kPump, kSyringe60 };
enum class AspirationOutcome : std::uint8_t { kIngested, kCorked, kLost };

inline constexpr double kPa_per_inHg = 3386.389;
inline constexpr double kWedgeStrain = 0.10;

// Gauge pressure of the source, Pa (negative).
[[nodiscard]] double vacuum_Pa(VacuumSource source);
[[nodiscard]] std::string_view vacuum_source_name(VacuumSource source);
// |pressure| x pi ID^2 / 4, N.
[[nodiscard]] double aspiration_force_N(VacuumSource source, double inner_diameter_mm);

struct AspirationClot {
  double diameter_mm = 3.0;  // the lumen it occludes
  double length_mm = 13.0;
  ClotComposition composition;
};

struct AspirationResult {
  AspirationOutcome outcome = AspirationOutcome::kLost;
  double force_N = 0.0;          // the vacuum's pull
  double ingest_force_N = 0.0;   // needed to draw the clot into the lumen
  double hold_force_N = 0.0;     // holding the clot in place on withdrawal
};

// What holds a lodged clot in place against a pull: its static wall friction under the wedge
// strain plus the pressure head across it on the lumen area, N (the corked withdrawal's hold;
// a stent retriever's pull on its integrated clot must exceed it too).
[[nodiscard]] double clot_hold_force_N(const AspirationClot& clot, double pressure_head_Pa);
// What resists a clot once it slides (dragged by a stent retriever): its kinetic wall friction
// under the wedge strain plus the pressure head on the lumen area, N.
[[nodiscard]] double clot_drag_force_N(const AspirationClot& clot, double pressure_head_Pa);

// What contact aspiration at this clot's face does, with `pressure_head_Pa` across the clot.
// Inputs outside their ranges (ID or clot sizes not positive and finite, a bad composition)
// are the caller's to check.
[[nodiscard]] AspirationResult aspirate(VacuumSource source, double inner_diameter_mm, const AspirationClot& clot, double pressure_head_Pa);

}  // namespace cathbox::flow
