#pragma once
// Releasing a coil in a test: detach, then the hand at rest while the detachment zone parts.
#include <cstddef>

#include "tool/coil_metrics.hpp"
#include "tool/simulator.hpp"

namespace cathbox::tool::testing {

// Detaches `tool`'s coil and steps until its detachment zone has parted and the coil is released
// (Simulator::detach: tuning::kDetachParting_s), observing `metrics` each step if given.
inline DeviceError release_coil(Simulator& sim, std::size_t tool, CoilMetrics* metrics = nullptr) {
  const DeviceError e = sim.detach(tool);
  while (e == DeviceError::kNone && sim.parting(tool)) {
    sim.step();
    if (metrics != nullptr) metrics->observe(sim);
  }
  return e;
}

}  // namespace cathbox::tool::testing
