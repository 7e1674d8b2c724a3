#pragma once
// A thrombus lodged in a vessel: where it is, how long, what it is made of, and how much of the
// lumen it leaves open. FlowNetwork::occlude() turns clots into flow resistance: the clot's
// length is a porous plug (Darcy's law, permeability kClotPermeability_m2) in parallel with
// whatever lumen stays open (a Poiseuille channel of the open area), instead of the open vessel
// over that length. A complete occlusion leaves the territory downstream the collaterals'
// flow only; removing the clot restores the open network exactly.
#include <cstdint>

#include "flow/clot_material.hpp"

namespace cathbox::flow {

// Hydraulic permeability of a contracted stroke thrombus, m^2: the order of magnitude of
// platelet-rich and dense fibrin clots (Wufsus, Macera & Neeves, Biophys J 2013: 1e-14 to
// 1e-12 m^2 across packing densities).
inline constexpr double kClotPermeability_m2 = 1e-13;

struct Clot {
  std::uint32_t segment = 0;    // index into the vessel model's segments
  double arc_start_mm = 0.0;    // proximal face: arc length from the segment's first point
  double length_mm = 13.0;
  ClotComposition composition;
  double open_fraction = 0.0;   // share of the lumen area left open, [0, 1): 0 occludes
  friend bool operator==(const Clot&, const Clot&) = default;
};

// An inflated balloon (a balloon guide catheter's) sealing a segment: no flow passes it, the
// flow arrest under which a clot is retrieved. Resistance kSealFactor times the segment's open
// resistance (finite, so the pressure system stays positive definite).
struct FlowArrest {
  std::uint32_t segment = 0;
  friend bool operator==(const FlowArrest&, const FlowArrest&) = default;
};
inline constexpr double kSealFactor = 1e12;

}  // namespace cathbox::flow
