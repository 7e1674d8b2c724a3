#include "scenario/scenario_runner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "scenario/script_player.hpp"
#include "base/text_lines.hpp"

namespace cathbox::tool {

using base::text::located;

namespace {

constexpr std::int64_t kMaxSteps = 3'700'000;  // the script's hour plus settling

}  // namespace

std::string apply_device_action(Simulator& sim, const ScriptPlayer::DeviceAction& a, std::string_view script_name) {
  DeviceError e = DeviceError::kNone;
  if (a.kind == ActionKind::kInflatePressure) e = sim.inflate_pressure(a.tool, a.value);
  if (a.kind == ActionKind::kInflateVolume) e = sim.inflate_volume(a.tool, a.value);
  if (a.kind == ActionKind::kDeflate) e = sim.deflate(a.tool);
  if (e == DeviceError::kNone) return {};
  const char* verb = a.kind == ActionKind::kDeflate ? "deflate: " : "inflate: ";
  const Balloon* b = sim.balloon(a.tool);
  if (e == DeviceError::kOutOfRange && a.kind == ActionKind::kInflateVolume && b != nullptr) {
    char what[160];
    std::snprintf(what, sizeof what, "%g ml is more than the balloon holds at %g atm (%.3f ml)", a.value,
                  Balloon::kMaxPressure_atm, b->volume_at(Balloon::kMaxPressure_atm));
    return located(script_name, a.line, verb + std::string(what));
  }
  return located(script_name, a.line, verb + std::string(device_error_text(e)));
}

void write_scenario_header(std::ostream& csv) {
  csv << "time_ms,tool,insertion_mm,rotation_rad,tip_x_mm,tip_y_mm,tip_z_mm,force_mN,torque_mNmm,contacts,tip_segment\n";
}

void write_scenario_row(std::ostream& csv, const Simulator& sim, std::int64_t time_ms) {
  const std::size_t t = sim.active_tool();
  const TipPose tip = sim.tip(t);
  char line[320];
  const int n = std::snprintf(line, sizeof line, "%lld,%s,%.4f,%.5f,%.4f,%.4f,%.4f,%.3f,%.3f,%zu,%d\n",
                              static_cast<long long>(time_ms), sim.rod(t).spec().name.c_str(), sim.insertion_mm(t),
                              sim.rotation_rad(t), tip.position_mm.x, tip.position_mm.y, tip.position_mm.z,
                              sim.hand_force_mN(t), sim.hand_torque_mNmm(t), sim.rod(t).contacts().size(),
                              static_cast<int>(sim.tip_segment(t)));
  if (n > 0) csv.write(line, std::min<std::streamsize>(n, static_cast<std::streamsize>(sizeof line) - 1));
}

ScenarioResult run_scenario(Simulator& sim, const Script& script, const ScenarioOptions& options, std::ostream& csv) {
  ScenarioResult result;
  std::vector<ScriptPlayer::ToolInfo> tools;
  for (std::size_t t = 0; t < sim.tool_count(); ++t) {
    tools.push_back(tool_info(sim.rod(t).spec()));
    tools.back().aspirator = true;  // no thrombectomy unit here: `aspiration` lines are passed over, not checked
  }
  // Every tool a script names must exist before anything runs.
  base::Result<ScriptPlayer> player = ScriptPlayer::make(script, tools, sim.active_tool(), options.script_name);
  if (!player) {
    result.error = player.error().message;
    return result;
  }
  const std::int64_t every = std::max<std::int64_t>(1, options.every_ms);
  std::optional<CoilMetrics> coils;
  if (options.sac != nullptr) coils.emplace(sim, *options.sac);
  if (coils && !coils->has_coils()) coils.reset();
  write_scenario_header(csv);
  for (std::int64_t now = 0; now < kMaxSteps; ++now) {
    const ScriptPlayer::Step step = player->advance(now);
    if (step.selected) sim.select(*step.selected);
    if (step.ended) break;
    if (step.detach) {
      const DeviceError e = sim.detach(*step.detach);
      if (e != DeviceError::kNone) result.notes.push_back(located(options.script_name, step.detach_line, std::string("detach: ") + device_error_text(e)));
    }
    if (step.load_coil) {
      const DeviceError e = sim.load_next_coil(*step.load_coil);
      if (e != DeviceError::kNone) {
        // The player has moved on to the next coil: its motions would pull the coil still
        // attached back to the hub. The run ends here.
        result.error = located(options.script_name, step.load_coil_line, std::string("load_coil: ") + device_error_text(e));
        return result;
      }
    }
    for (std::size_t i = 0; i < step.device_count; ++i) {
      if (std::string e = apply_device_action(sim, step.devices[i], options.script_name); !e.empty()) {
        result.error = std::move(e);
        return result;
      }
    }
    for (std::size_t t = 0; t < sim.tool_count(); ++t) {
      sim.set_insertion(t, player->insertion_mm(t));
      sim.set_rotation(t, player->rotation_rad(t));
    }
    sim.step(1e-3);
    if (options.angioplasty != nullptr) options.angioplasty->after_step(sim);
    if (options.after_step) options.after_step(sim);
    ++result.steps;
    if (coils) coils->observe(sim);
    const std::int64_t time_ms = now + 1;
    if (time_ms % every == 0) {
      write_scenario_row(csv, sim, time_ms);
      ++result.rows;
    }
    if (player->settled(now, options.settle_ms)) break;
  }
  if (coils) result.coils = coils->figures();
  if (options.angioplasty != nullptr) result.angioplasty = options.angioplasty->figures(sim);
  result.ok = true;
  return result;
}

}  // namespace cathbox::tool
