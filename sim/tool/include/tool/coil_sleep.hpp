#pragma once
// Sleeping released coils: a detached coil that has come to rest is not solved while nothing
// near it moves; it stays where it is, a frozen obstacle to the other rods (as every other rod
// already is while one is solved, RodContactField).
//
// Rest is judged in the solver's own units: a converged step's positions are known to its
// tolerance (`RodSettings::convergence_mm`, 2 um), so a coil rests once, for `rest_ticks`
// consecutive ticks (the solves on its turns covering them, Simulator::set_released_turn_ticks),
// (a) no node moved more than `rest_share` of that tolerance in a solve and
// (b) no node drifted, net over those steps, more than `drift_share` of it: a steady creep of a
// fraction of a micrometre a tick is not frozen unknowingly.
//
// The wake is decided before the sleeping coil's own solve in the step, from the rods solved
// before it (the attached tools, then the released coils in order): right after each rod's
// solve its nodes' moves are recorded against every sleeping coil within its contact reach (the
// two radii, the field's margin, half an edge and a skin); a coil whose recorded moves sum to more
// than `wake_move_mm` is solved in that same step, from where it slept, with no warm start. In
// the simulator's order every rod sees the others where their last solve left them, so a coil
// asleep is what the same coil awake would be, but for its own drift while asleep (bounded by
// the rest test) and neighbour moves under `wake_move_mm`. A rod whose node count changed (a
// pusher at detachment, a coil loaded) wakes every sleeping coil it is near. A replaced or moved
// wall wakes every coil (the Simulator watches `WallModel::revision()`). Every decision reads node
// positions only: the same inputs give the same sleeps, so a record replays with its state hashes.
// Nothing allocates per step once every rod's node count has been seen.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "tool/rod.hpp"

namespace cathbox::tool {

class CoilSleep {
 public:
  struct Settings {
    bool enabled = true;
    double rest_share = 0.5;      // of the coil's convergence_mm: a node's largest move a tick at rest
    double drift_share = 1.0;     // of the coil's convergence_mm: a node's net move over the window
    int rest_ticks = 200;         // the window, 0.2 s
    double wake_move_mm = 1e-4;   // neighbours within reach moving 0.1 um in all wake it
    double skin_mm = 0.1;         // added to the contact reach
  };

  CoilSleep() = default;
  explicit CoilSleep(const Settings& s) : settings_(s) {}
  [[nodiscard]] Settings& settings() { return settings_; }

  // Coil i (of the simulator's detached coils) is not to be solved now.
  [[nodiscard]] bool asleep(std::size_t coil) const { return coil < coils_.size() && coils_[coil].asleep; }
  [[nodiscard]] std::size_t asleep_count() const;
  // Times a coil woke, and coil steps skipped, since construction (diagnostics, benches).
  [[nodiscard]] std::uint64_t wakes() const { return wakes_; }
  [[nodiscard]] std::uint64_t skipped_steps() const { return skipped_; }

  // The simulator's step, in its order: begin(), tool_solved() after each attached tool's solve,
  // then for each released coil wake_before() (true: solve it) and coil_solved() after its solve
  // or its skipped turn. `margin_mm` is the rod-contact field's.
  void begin(std::span<const Rod> tools, std::span<const Rod> coils);
  void tool_solved(std::size_t t, std::span<const Rod> tools, std::span<const Rod> coils, double margin_mm);
  [[nodiscard]] bool wake_before(std::size_t i, std::span<const Rod> coils);
  // `ticks`: the steps the coil's solve covered (Simulator::set_released_turn_ticks); the rest
  // window counts ticks.
  void coil_solved(std::size_t i, std::span<const Rod> coils, double margin_mm, int ticks = 1);
  // Every coil is solved again (the wall was replaced, or sleeping was switched off).
  void wake_all();

 private:
  struct Chunk {  // a run of a sleeping coil's nodes, bounded by a sphere
    glm::dvec3 centre{0.0};
    double reach = 0.0;  // its bounding radius plus the largest node reach in it
    std::size_t first = 0, last = 0;
  };
  struct Coil {
    bool asleep = false;
    int still = 0;           // consecutive steps at rest
    double disturbed = 0.0;  // summed neighbour motion while asleep
    glm::dvec3 lo{0.0}, hi{0.0};  // bounds of its nodes' reach while asleep
    std::size_t chunk_first = 0, chunk_count = 0;
  };
  void fall_asleep(std::size_t i, const Rod& coil);
  void rebuild_chunks(std::span<const Rod> coils);
  double disturb(const Rod& rod, std::vector<glm::dvec3>& last, std::span<const Rod> coils, double margin_mm);
  [[nodiscard]] bool near(const Coil& c, const Rod& coil, const glm::dvec3& p, double r, double margin_mm) const;
  [[nodiscard]] bool at_rest(std::size_t i, const Rod& coil, double move, int ticks);

  Settings settings_;
  std::vector<Coil> coils_;
  std::vector<Chunk> chunks_;
  std::vector<std::vector<glm::dvec3>> tool_last_, coil_last_;  // positions after the last solve
  std::vector<std::vector<glm::dvec3>> window_;  // each coil's positions where its rest window began
  std::uint64_t wakes_ = 0;
  std::uint64_t skipped_ = 0;
};

}  // namespace cathbox::tool
