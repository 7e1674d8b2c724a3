#pragma once
// An aspiration catheter's vacuum holding a thrombus (thrombectomy_unit.hpp, "Engagement"): which
// catheter holds which clots, by the unit's clot ids (stable while a clot remains, so a pass that
// takes clots out leaves the others' ids as they were), how far the catheter has been withdrawn
// since it engaged, and the vacuum's verdict on the thrombus (flow::aspirate, Froehler 2017:
// ingested, corked or lost) with the pull it puts on the tip. host/session/README.md, "Thrombectomy".
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "flow/aspiration.hpp"

namespace cathbox::session {

// A clot's id in the thrombectomy unit: given once (the case's clots in order, then each embolus
// as it lodges), never reused.
using ClotId = std::uint32_t;

// The engaged catheter withdrawn this far below its deepest insertion since it engaged ends the pass.
inline constexpr double kPassWithdrawal_mm = 10.0;

// A catheter the case aspirates through.
struct Aspirator {
  std::size_t tool = 0;
  flow::VacuumSource source = flow::VacuumSource::kPump;
  double inner_diameter_mm = 0.0;
  double length_mm = 0.0;  // the catheter's (its sections): its lumen's Poiseuille resistance

  // The vacuum's verdict on `clot` with `head_Pa` across it: ingested, corked or lost.
  [[nodiscard]] flow::AspirationResult verdict(const flow::AspirationClot& clot, double head_Pa) const;
  // The pull, mN, the held clot puts on the tip: none when it would be ingested (it slides into
  // the lumen), else the smaller of the vacuum's force and what holds the clot in place.
  [[nodiscard]] double grip_mN(const flow::AspirationClot& clot, double head_Pa) const;
};

class VacuumHold {
 public:
  // Catheter `tool`'s vacuum takes hold of `thrombus` with the catheter in at `insertion_mm`.
  void engage(std::size_t tool, std::vector<ClotId> thrombus, double insertion_mm);
  // The held catheter's insertion now: true once it is kPassWithdrawal_mm below its deepest
  // since it engaged (the pass ends).
  [[nodiscard]] bool withdrawn(double insertion_mm);
  // Lets go (aspiration off, or the pass ended).
  void release();
  // Another device's pass took `removed` out: a hold on any of them ends (true: the tip is open,
  // its sink draws again); a hold on clots the pass left keeps them.
  bool release_removed(std::span<const ClotId> removed);

  [[nodiscard]] std::optional<std::size_t> tool() const { return tool_; }
  [[nodiscard]] bool on(std::size_t tool) const { return tool_ == tool; }
  [[nodiscard]] bool holds(ClotId clot) const;
  [[nodiscard]] const std::vector<ClotId>& thrombus() const { return thrombus_; }

 private:
  std::optional<std::size_t> tool_;
  std::vector<ClotId> thrombus_;  // its face first
  double deepest_mm_ = 0.0;
};

}  // namespace cathbox::session
