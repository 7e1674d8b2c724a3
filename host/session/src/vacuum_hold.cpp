#include "session/vacuum_hold.hpp"

#include <algorithm>
#include <utility>

namespace cathbox::session {

flow::AspirationResult Aspirator::verdict(const flow::AspirationClot& clot, double head_Pa) const {
  return flow::aspirate(source, inner_diameter_mm, clot, head_Pa);
}

double Aspirator::grip_mN(const flow::AspirationClot& clot, double head_Pa) const {
  const flow::AspirationResult r = verdict(clot, head_Pa);
  return r.outcome == flow::AspirationOutcome::kIngested ? 0.0 : 1000.0 * std::min(r.force_N, r.hold_force_N);
}

void VacuumHold::engage(std::size_t tool, std::vector<ClotId> thrombus, double insertion_mm) {
  tool_ = tool;
  thrombus_ = std::move(thrombus);
  deepest_mm_ = insertion_mm;
}

bool VacuumHold::withdrawn(double insertion_mm) {
  deepest_mm_ = std::max(deepest_mm_, insertion_mm);
  return insertion_mm <= deepest_mm_ - kPassWithdrawal_mm;
}

void VacuumHold::release() {
  tool_.reset();
  thrombus_.clear();
}

bool VacuumHold::release_removed(std::span<const ClotId> removed) {
  if (!tool_ || std::none_of(thrombus_.begin(), thrombus_.end(), [&](ClotId k) { return std::find(removed.begin(), removed.end(), k) != removed.end(); })) {
    return false;
  }
  release();
  return true;
}

bool VacuumHold::holds(ClotId clot) const { return tool_.has_value() && std::find(thrombus_.begin(), thrombus_.end(), clot) != thrombus_.end(); }

}  // namespace cathbox::session
