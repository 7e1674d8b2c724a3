#pragma once
// The headless runner behind `cathbox sim run`: plays an action script on a simulator in
// virtual time (1 ms steps) and writes one CSV row per logged step:
//   time_ms,tool,insertion_mm,rotation_rad,tip_x_mm,tip_y_mm,tip_z_mm,force_mN,torque_mNmm,contacts,tip_segment
// for the selected tool. The same inputs give byte-identical output.
#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include <optional>

#include "scenario/action_script.hpp"
#include "tool/coil_metrics.hpp"
#include "tool/angioplasty.hpp"
#include "scenario/script_player.hpp"
#include "tool/simulator.hpp"

namespace cathbox::tool {

struct ScenarioOptions {
  std::int64_t every_ms = 1;        // log every this many steps
  std::string script_name = "script";  // for file:line errors
  std::int64_t settle_ms = 100;     // run on after the last motion ends (when there is no 'end')
  const AneurysmSac* sac = nullptr; // with coil tools: their figures (coil_metrics.hpp) in the result
  // With a balloon: the lumen it widens and the walls swapped in (after every step); its
  // figures come back in the result. Not owned; the simulator must use its wall.
  Angioplasty* angioplasty = nullptr;
  // Called after every step (tests use it to watch per-tick state, e.g. contact forces).
  std::function<void(const Simulator&)> after_step;
};

struct ScenarioResult {
  bool ok = false;
  std::string error;  // "file:line: message" for a script that does not fit the case
  std::uint64_t steps = 0;
  std::uint64_t rows = 0;
  std::vector<std::string> notes;    // "file:line: detach: why it was refused" (the run goes on;
                                     // a refused load_coil ends it with `error`)
  std::optional<CoilFigures> coils;  // with a sac and coil tools
  std::optional<AngioplastyFigures> angioplasty;  // with options.angioplasty
};

[[nodiscard]] ScenarioResult run_scenario(Simulator& sim, const Script& script, const ScenarioOptions& options,
                                          std::ostream& csv);

// Applies a balloon action of the script to the simulator: empty, or one line
// "file:line: inflate: <why it was refused>" (e.g. a volume the balloon cannot take).
[[nodiscard]] std::string apply_device_action(Simulator& sim, const ScriptPlayer::DeviceAction& a,
                                              std::string_view script_name);

// The log's header line and one row for the selected tool (also `cathbox session replay --out`).
void write_scenario_header(std::ostream& csv);
void write_scenario_row(std::ostream& csv, const Simulator& sim, std::int64_t time_ms);

}  // namespace cathbox::tool
