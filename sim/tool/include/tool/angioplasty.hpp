#pragma once
// Balloon angioplasty in the running simulation: after every Simulator::step() the balloon
// presses the lumen (LumenRemodel); a lumen that changed asks for a new wall (WallSwap), which
// is swapped into the simulator between two ticks when due. The first balloon tool of the
// simulator is the one followed.
//
//   auto world = build_world(c);                                   // an HCLM vessel
//   Angioplasty angio(*(*world)->source_model(), (*world)->release_wall(), WallSwap::Mode::kSynchronous);
//   Simulator sim(angio.wall(), c.tools, (*world)->entry());
//   ... each tick: sim.step(1e-3); angio.after_step(sim);
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "tool/lumen_remodel.hpp"
#include "tool/simulator.hpp"
#include "tool/wall_swap.hpp"

namespace cathbox::tool {

// The figures of an angioplasty run (cathbox sim run and the session report them).
struct AngioplastyFigures {
  bool lesion = false;              // a stenosis was found in the vessel
  double stenosis_before_percent = 0.0;
  double residual_stenosis_percent = 0.0;
  double reference_diameter_mm = 0.0;
  int inflations = 0;
  double inflated_time_s = 0.0;
  double max_pressure_atm = 0.0;
  bool over_rated_burst = false;
  int rupture_risk_events = 0;      // over-sized inflations (LumenRemodelParams::oversize_ratio)
  double max_oversize_ratio = 0.0;
  std::uint64_t wall_swaps = 0;
  std::uint64_t swap_waits = 0;     // swaps whose due tick waited for the worker (live runs only)
};

class Angioplasty {
 public:
  Angioplasty(vessel::VesselModel source, std::unique_ptr<WallModel> wall, WallSwap::Mode mode,
              const LumenRemodelParams& params = {}, WallBuilder builder = cached_mesh_wall_builder(),
              std::int64_t latency_ticks = WallSwap::kDefaultLatencyTicks);

  [[nodiscard]] const WallModel& wall() const { return swap_.wall(); }
  // Call after each Simulator::step(), on the thread that steps it.
  void after_step(Simulator& sim);
  [[nodiscard]] AngioplastyFigures figures(const Simulator& sim) const;

  [[nodiscard]] const LumenRemodel& lumen() const { return lumen_; }
  [[nodiscard]] WallSwap& swap() { return swap_; }
  [[nodiscard]] const WallSwap& swap() const { return swap_; }

 private:
  LumenRemodel lumen_;
  WallSwap swap_;
  std::vector<glm::dvec3> axis_;  // scratch (keeps its storage)
  bool dirty_ = false;            // the lumen moved away from the last wall asked for
};

// The first tool of `sim` carrying a balloon, or tool_count().
[[nodiscard]] std::size_t first_balloon_tool(const Simulator& sim);

}  // namespace cathbox::tool
