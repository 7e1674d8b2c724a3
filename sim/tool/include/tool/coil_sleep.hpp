#pragma once
// Sleeping released coils: a detached coil that has come to rest is not solved while nothing
// near it moves; it stays where it is, a frozen obstacle to the other rods (as every other rod
// already is while one is solved, RodContactField). It falls asleep after `rest_ticks`
// consecutive steps in which no node moved more than `rest_move_mm`; it wakes when the nodes of
// the rods still solved (attached tools and awake coils) that lie within its contact reach
// (the two radii, the field's margin, half an edge and a skin) have moved, summed over the
// steps it slept (the largest such move of each step), more than `wake_move_mm`, or when the
// wall is replaced or moves in place (the Simulator watches `WallModel::revision()`). Every
// decision reads node positions only, after the step, and takes effect at the next: the same
// inputs give the same sleeps, so a record replays with its state hashes. Nothing allocates per step once every rod's node count has been seen.
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
    double rest_move_mm = 1e-5;   // 0.01 um a tick
    int rest_ticks = 200;         // for 0.2 s
    double wake_move_mm = 1e-4;   // neighbours within reach moving 0.1 um in all wake it
    double skin_mm = 0.1;         // added to the contact reach
  };

  CoilSleep() = default;
  explicit CoilSleep(const Settings& s) : settings_(s) {}
  [[nodiscard]] Settings& settings() { return settings_; }

  // Coil i (of the simulator's detached coils) is not to be solved this step.
  [[nodiscard]] bool asleep(std::size_t coil) const { return coil < coils_.size() && coils_[coil].asleep; }
  [[nodiscard]] std::size_t asleep_count() const;
  // Times a coil woke, and coil steps skipped, since construction (diagnostics, benches).
  [[nodiscard]] std::uint64_t wakes() const { return wakes_; }
  [[nodiscard]] std::uint64_t skipped_steps() const { return skipped_; }

  // After a step: each coil's own motion, the motion near each sleeping coil, the decisions
  // for the next step. `margin_mm` is the rod-contact field's.
  void observe(std::span<const Rod> tools, std::span<const Rod> coils, double margin_mm);
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

  Settings settings_;
  std::vector<Coil> coils_;
  std::vector<Chunk> chunks_;
  std::vector<std::vector<glm::dvec3>> tool_last_, coil_last_;  // positions after the last step
  std::vector<double> step_disturb_;  // per coil, this step's largest neighbour move
  std::uint64_t wakes_ = 0;
  std::uint64_t skipped_ = 0;
};

}  // namespace cathbox::tool
