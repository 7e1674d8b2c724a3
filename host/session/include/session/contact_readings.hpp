#pragma once
// The wall contact forces the metrics and the event log read from the simulator, one reading
// per snapshot tool per tick (the case's tools, then the coils released so far, in the
// snapshot's order): its largest contact force, and whether its tip (its last 3 nodes) touches
// the wall and with what force. A tool's reading is taken only from a step whose solve
// converged (tool::Rod::converged()); after a step that ran out of iterations the tool keeps
// its last converged reading. The penalty contacts read force from penetration at 2·10^5
// mN/mm, so an unconverged step's leftover penetration of a few micrometres reads hundreds of
// mN to the cap (5 % of the radius: 1.8 N for a 0.36 mm wire, 3.5 N for a 0.7 mm
// microcatheter) for a tick, and these were what the "tip on the wall" event and the peak wall
// force showed (host/session/README.md, "Wall forces").
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tool/simulator.hpp"
#include "tool/snapshot.hpp"

namespace cathbox::session {

class ContactReadings {
 public:
  struct Reading {
    double wall_mN = 0.0;         // largest normal force of the tool's contacts
    bool tip_in_contact = false;  // a contact on one of its last 3 nodes
    double tip_mN = 0.0;          // largest normal force on those
  };
  static constexpr std::uint32_t kTipNodes = 3;

  explicit ContactReadings(std::size_t tools) : readings_(tools), held_ticks_(tools, 0), solved_ticks_(tools, 0) {}

  // After each step: the readings of the tools whose step converged (or that have no free
  // node), from the snapshot's contacts; the others keep theirs. A coil released since the
  // last update gets a reading of its own (sim.released_view(), after sim.tool_count() tools).
  void update(const tool::Simulator& sim, const tool::Snapshot& snap);

  [[nodiscard]] const Reading& tool(std::size_t t) const { return readings_[t]; }
  // Readings held: the tools constructed with, or the snapshot's tools once coils are released.
  [[nodiscard]] std::size_t size() const { return readings_.size(); }
  // Largest of every tool's wall reading.
  [[nodiscard]] double wall_mN() const;
  // Ticks a tool's reading was kept from an earlier step (its step did not converge).
  [[nodiscard]] std::int64_t held_ticks(std::size_t t) const { return held_ticks_[t]; }
  // Ticks the tool had a step to solve (a free node past the entry): held_ticks ÷ solved_ticks
  // is its unconverged share, what the metrics report as `unconverged_pct`.
  [[nodiscard]] std::int64_t solved_ticks(std::size_t t) const { return solved_ticks_[t]; }

 private:
  std::vector<Reading> readings_;
  std::vector<std::int64_t> held_ticks_;
  std::vector<std::int64_t> solved_ticks_;
};

}  // namespace cathbox::session
