#include "flow/aspiration.hpp"

#include <algorithm>
#include <numbers>

namespace cathbox::flow {
namespace {


double area_mm2(double diameter_mm) { return 0.25 * std::numbers::pi * diameter_mm * diameter_mm; }

// The clot's wall load under the wedge strain and its head term, N.
double wedge_wall_N(const AspirationClot& clot) {
  return ClotCompressionLaw(clot.composition).stress_kPa(kWedgeStrain) * 1e3 * std::numbers::pi * clot.diameter_mm * clot.length_mm * 1e-6;
}
double head_N(const AspirationClot& clot, double pressure_head_Pa) { return std::max(0.0, pressure_head_Pa) * area_mm2(clot.diameter_mm) * 1e-6; }

}  // namespace

double vacuum_Pa(VacuumSource source) {
  // Froehler 2017: the Penumbra pump -25.6 inHg, a 60 mL locking syringe -27.0 inHg.
  return (source == VacuumSource::kPump ? -25.6 : -27.0) * kPa_per_inHg;
}

std::string_view vacuum_source_name(VacuumSource source) { return source == VacuumSource::kPump ? "pump" : "syringe"; }

double aspiration_force_N(VacuumSource source, double inner_diameter_mm) {
  return -vacuum_Pa(source) * area_mm2(inner_diameter_mm) * 1e-6;
}

double clot_hold_force_N(const AspirationClot& clot, double pressure_head_Pa) {
  return clot_wall_friction(clot.composition).static_coefficient * wedge_wall_N(clot) + head_N(clot, pressure_head_Pa);
}

double clot_drag_force_N(const AspirationClot& clot, double pressure_head_Pa) {
  return clot_wall_friction(clot.composition).kinetic_coefficient * wedge_wall_N(clot) + head_N(clot, pressure_head_Pa);
}

AspirationResult aspirate(VacuumSource source, double inner_diameter_mm, const AspirationClot& clot, double pressure_head_Pa) {
  AspirationResult r;
  r.force_N = aspiration_force_N(source, inner_diameter_mm);
  const ClotCompressionLaw law(clot.composition);
  const ClotFriction friction = clot_wall_friction(clot.composition);
  const double strain = std::max(0.0, 1.0 - inner_diameter_mm / clot.diameter_mm);
  r.ingest_force_N = friction.kinetic_coefficient * law.stress_kPa(strain) * 1e3 * std::numbers::pi * inner_diameter_mm * clot.length_mm * 1e-6;
  r.hold_force_N = clot_hold_force_N(clot, pressure_head_Pa);
  if (strain <= 0.0 || r.force_N > r.ingest_force_N) {
    r.outcome = AspirationOutcome::kIngested;
  } else {
    r.outcome = r.force_N > r.hold_force_N ? AspirationOutcome::kCorked : AspirationOutcome::kLost;
  }
  return r;
}

}  // namespace cathbox::flow
