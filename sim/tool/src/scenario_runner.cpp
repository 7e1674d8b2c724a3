#include "tool/scenario_runner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "tool/text_lines.hpp"

namespace cathbox::tool {

namespace {

constexpr double kDegToRad = M_PI / 180.0;
constexpr std::int64_t kMaxSteps = 3'700'000;  // the script's hour plus settling

struct Motion {
  bool active = false;
  double target = 0.0;
  double speed_per_ms = 0.0;
};

// Moves `value` towards the motion's target by one millisecond.
double advance(Motion& m, double value) {
  if (!m.active) return value;
  const double d = m.target - value;
  if (std::abs(d) <= m.speed_per_ms) {
    m.active = false;
    return m.target;
  }
  return value + (d > 0.0 ? m.speed_per_ms : -m.speed_per_ms);
}

void write_row(std::ostream& csv, const Simulator& sim, std::int64_t time_ms) {
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

}  // namespace

ScenarioResult run_scenario(Simulator& sim, const Script& script, const ScenarioOptions& options, std::ostream& csv) {
  ScenarioResult result;
  // Every tool a script names must exist before anything runs.
  for (const Action& a : script.actions) {
    if (a.kind == ActionKind::kSelect && sim.find_tool(a.tool) >= sim.tool_count()) {
      std::string known;
      for (std::size_t i = 0; i < sim.tool_count(); ++i) known += (i ? " " : "") + sim.rod(i).spec().name;
      result.error = located(options.script_name, a.line, "select: the case has no tool '" + a.tool + "' (tools: " + known + ")");
      return result;
    }
  }
  const std::int64_t every = std::max<std::int64_t>(1, options.every_ms);
  std::vector<Motion> insert(sim.tool_count()), rotate(sim.tool_count());
  std::vector<double> ins(sim.tool_count(), 0.0), rot(sim.tool_count(), 0.0);
  std::int64_t end_ms = -1;
  std::int64_t last_action_ms = script.actions.empty() ? 0 : script.actions.back().time_ms;
  csv << "time_ms,tool,insertion_mm,rotation_rad,tip_x_mm,tip_y_mm,tip_z_mm,force_mN,torque_mNmm,contacts,tip_segment\n";
  std::size_t next = 0;
  std::int64_t idle_since = -1;
  for (std::int64_t now = 0; now < kMaxSteps; ++now) {
    for (; next < script.actions.size() && script.actions[next].time_ms <= now; ++next) {
      const Action& a = script.actions[next];
      const std::size_t t = sim.active_tool();
      switch (a.kind) {
        case ActionKind::kSelect: sim.select(sim.find_tool(a.tool)); break;
        case ActionKind::kEnd: end_ms = a.time_ms; break;
        case ActionKind::kInsertTo:
        case ActionKind::kInsertBy:
          insert[t].active = true;
          insert[t].target = a.kind == ActionKind::kInsertTo ? a.value : ins[t] + a.value;
          insert[t].target = std::clamp(insert[t].target, 0.0, sim.rod(t).max_insertion_mm());
          insert[t].speed_per_ms = a.speed / 1000.0;
          break;
        case ActionKind::kRotateTo:
        case ActionKind::kRotateBy:
          rotate[t].active = true;
          rotate[t].target = a.kind == ActionKind::kRotateTo ? a.value * kDegToRad : rot[t] + a.value * kDegToRad;
          rotate[t].speed_per_ms = a.speed * kDegToRad / 1000.0;
          break;
        case ActionKind::kFluoro:
        case ActionKind::kInject:
        case ActionKind::kCArm:
        case ActionKind::kRoadmap:
          break;  // imaging: acted on by the session and the trainer, not by the tool log
      }
    }
    if (end_ms >= 0 && now >= end_ms) break;
    bool moving = false;
    for (std::size_t t = 0; t < sim.tool_count(); ++t) {
      ins[t] = advance(insert[t], ins[t]);
      rot[t] = advance(rotate[t], rot[t]);
      moving = moving || insert[t].active || rotate[t].active;
      sim.set_insertion(t, ins[t]);
      sim.set_rotation(t, rot[t]);
    }
    sim.step(1e-3);
    ++result.steps;
    const std::int64_t time_ms = now + 1;
    if (time_ms % every == 0) {
      write_row(csv, sim, time_ms);
      ++result.rows;
    }
    if (end_ms < 0 && next >= script.actions.size() && now >= last_action_ms) {
      if (moving) {
        idle_since = -1;
      } else if (idle_since < 0) {
        idle_since = now;
      } else if (now - idle_since >= options.settle_ms) {
        break;
      }
    }
  }
  result.ok = true;
  return result;
}

}  // namespace cathbox::tool
