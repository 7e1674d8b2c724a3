#pragma once
// The hand force a session's held tool gets, tick by tick, and what the box renders of it: the
// observer and the virtual-time run shared by the hand-force replays (hand_force_replay_test.cpp)
// and the dense coiling run (dense_coiling_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "session/action_script_hand.hpp"
#include "session/passive_law.hpp"
#include "session/session.hpp"
#include "session/tool_forces.hpp"

namespace cathbox::session::test {

constexpr double kFullScale_mN = 5000.0;       // the box's insertion full scale
constexpr double kSlewPerTick_mN = 100.0;      // the box's slew limit per 1 ms tick
constexpr double kUnconvergedMax_pct = 0.5;    // issue 29: every tool converges on ≥ 99.5 % of ticks
constexpr double kRounding_mN = 1e-6;          // a slew step met exactly, less its rounding

struct FeelRun {
  const char* name;
  const char* case_file;  // relative to the source tree, or absolute
  const char* actions;
  bool stent_short_wait = false;  // the bundled stent retriever run with its wait cut (stent_short_wait.hpp)
};

// Per tick: the held tool's hand force and its change since the last tick with the same tool.
class HandForceTrace : public TickObserver {
 public:
  void observe(const TickView& v) override {
    const double f = v.snapshot.tools[v.input.held].hand_force_mN;
    // The changes a tick: the held tool's as `cathbox session replay --forces` counts them; a tick
    // it starts afresh (another tool, a coil loaded) starts the box's law afresh too.
    forces_.count_changes_from(jumps_from_us);
    forces_.observe(v);
    render(v, forces_.held().fresh);
    max_jump_mN = forces_.held().largest_change_mN;
    max_jump_ms = forces_.held().change_us / 1000;
    ticks_over_slew = forces_.held().over_slew;
    if (std::abs(f) > peak_mN) {
      peak_mN = std::abs(f);
      peak_ms = v.time_us / 1000;
    }
    if (std::abs(f) > kSlewPerTick_mN) ++ticks_over_100mN;
    // The solver's own word as the tick reads it, per rod (the case's tools, then the released
    // coils: Simulator::released_view, a coil still being solved as the step began), to check the
    // metrics' unconverged shares against.
    const std::size_t tools = v.sim.tool_count();
    const std::size_t rods = tools + v.sim.detached_count();
    unconverged.resize(rods, 0);
    solved.resize(rods, 0);
    for (std::size_t t = 0; t < rods; ++t) {
      const tool::Rod& rod = t < tools ? v.sim.rod(t) : v.sim.released_view(t - tools);  // as the tick reads it
      if (rod.first_free_node() >= rod.node_total()) continue;
      ++solved[t];
      if (!rod.converged()) ++unconverged[t];
    }
    ++ticks;
  }
  std::int64_t jumps_from_us = 0;  // set before the run: the changes below counted from then on
  std::int64_t ticks = 0;
  double peak_mN = 0.0;
  std::int64_t peak_ms = 0;
  double max_jump_mN = 0.0;
  std::int64_t max_jump_ms = 0;
  std::int64_t ticks_over_slew = 0;   // change > 100 mN from the last tick
  std::int64_t ticks_over_100mN = 0;  // |force| > 100 mN
  std::vector<std::int64_t> unconverged, solved;  // per rod
  // What the box renders (resisting +): PassiveLaw's shaped law at the hand's position and speed.
  double rendered_peak_mN = 0.0;
  double rendered_max_jump_mN = 0.0;
  std::int64_t rendered_max_jump_ms = 0;
  std::int64_t rendered_ticks_over_slew = 0;
  // The largest difference between what the box renders and the tool's own force, and when.
  double rendered_off_mN = 0.0;
  std::int64_t rendered_off_ms = 0;
  // The same over the ticks the hand advanced the tool together with the catheter round it (by
  // the same micrometres: nothing slides in its valve or lumen), and how many there were.
  double carried_off_mN = 0.0;
  std::int64_t carried_off_ms = 0;
  std::int64_t carried_ticks = 0;
  // The held tool's own force on the last tick the hand pushed in (the end of the push).
  double pushed_force_mN = 0.0;
  double pushed_to_mm = 0.0;
  // Every tick the hand pushed in: the held tool, the hand's speed and the tool's own force.
  struct Push {
    std::size_t tool = 0;
    double speed_mm_s = 0.0, force_mN = 0.0;
  };
  std::vector<Push> pushes;

 private:
  // BoxHand::feel's path (box_hand.cpp): the law to the box's frame (here the session's: the
  // scripted hand has no count origin, and a translation changes no force), shaped with the box's
  // readback, which an ideal box reports as the output it rendered at the hand's position and
  // speed. The limits are PassiveLawLimits' defaults, the emulated box's (5 N, 100 mN/ms, 1 ms).
  void render(const TickView& v, bool fresh) {
    const double x = static_cast<double>(v.input.tools[v.input.held].insertion_um) * 1e-3;
    const std::size_t outer = v.sim.outer_of(v.input.held);
    const std::int64_t carrier_um = outer < v.sim.tool_count() ? v.input.tools[outer].insertion_um : 0;
    const std::int64_t hand_um = v.input.tools[v.input.held].insertion_um;
    const bool carried = !fresh && outer < v.sim.tool_count() && outer == carrier_of_ && hand_um > hand_um_ &&
                         hand_um - hand_um_ == carrier_um - carrier_um_;
    const double speed = fresh ? 0.0 : (x - hand_mm_) / (static_cast<double>(v.time_us - time_us_) * 1e-6);
    if (fresh) {
      box_law_.reset();
      readback_ = {};
    }
    const ShapedLaw shaped = box_law_.shape(v.sim.force_law(v.input.held), readback_);
    const double out = shaped.output_mN(x, speed);
    if (!fresh) {
      const double jump = std::abs(-out - rendered_mN_);
      if (jump > rendered_max_jump_mN) {
        rendered_max_jump_mN = jump;
        rendered_max_jump_ms = v.time_us / 1000;
      }
      if (jump > kSlewPerTick_mN + kRounding_mN) ++rendered_ticks_over_slew;
      if (speed > 0.0) {
        pushed_force_mN = v.snapshot.tools[v.input.held].hand_force_mN;
        pushed_to_mm = x;
        pushes.push_back({v.input.held, speed, pushed_force_mN});
      }
    }
    rendered_peak_mN = std::max(rendered_peak_mN, std::abs(out));
    const double off = std::abs(-out - v.snapshot.tools[v.input.held].hand_force_mN);
    if (off > rendered_off_mN) {
      rendered_off_mN = off;
      rendered_off_ms = v.time_us / 1000;
    }
    if (carried) {
      ++carried_ticks;
      if (off > carried_off_mN) {
        carried_off_mN = off;
        carried_off_ms = v.time_us / 1000;
      }
    }
    carrier_of_ = outer;
    carrier_um_ = carrier_um;
    hand_um_ = hand_um;
    readback_ = {out, speed};
    rendered_mN_ = -out;
    hand_mm_ = x;
    time_us_ = v.time_us;
  }
  PassiveLaw box_law_;
  BoxReadback readback_;
  double rendered_mN_ = 0.0;
  double hand_mm_ = 0.0;
  std::int64_t hand_um_ = 0, carrier_um_ = 0;
  std::size_t carrier_of_ = 0;
  std::int64_t time_us_ = 0;

  ToolForces forces_;
};

// Runs a case with its script as a session in virtual time, to its end; prints the figures.
// Every tool's unconverged share within issue 29's bound.
inline void expect_every_tool_converged(const Metrics& m) {
  for (const ToolConvergence& c : m.convergence) EXPECT_LE(c.unconverged_pct(), kUnconvergedMax_pct) << c.tool;
}

// Runs a case with an action script (both paths as given) in virtual time to its end, `observer`
// on every tick; the run's metrics. `spec`, when given, gets the loaded case; `setup`, when given,
// is called with the loaded case and the session before the first tick (to add an observer that
// needs the case's world). False (a test failure recorded) when the case or the script does not load.
inline bool run_scripted(const std::string& case_file, const std::string& actions, TickObserver& observer, Metrics& metrics,
                         tool::Case* spec = nullptr,
                         const std::function<void(const SessionCase&, Session&)>& setup = {}) {
  SessionCaseLoad loaded = load_session_case(case_file);
  EXPECT_TRUE(loaded) << (loaded ? "" : loaded.error().message);
  if (!loaded) return false;
  if (spec != nullptr) *spec = loaded.value()->spec;
  auto script = ActionScriptHand::load(actions, *loaded.value());
  EXPECT_TRUE(script) << (script ? "" : script.error().message);
  if (!script) return false;
  Session s(std::move(loaded.value()), std::move(*script));
  s.add_observer(observer);
  if (setup) setup(s.scene(), s);
  while (!s.over() && s.step_virtual(1000) > 0) {
  }
  metrics = s.metrics();
  return true;
}

// A FeelRun's session with the held tool's trace; prints the figures.
inline HandForceTrace run_session(const FeelRun& run, Metrics& metrics, tool::Case* spec = nullptr,
                                  const std::function<void(const SessionCase&, Session&)>& setup = {}) {
  HandForceTrace trace;
  const auto path = [](const char* file) {  // relative to the source tree, or absolute
    return file[0] == '/' ? std::string(file) : std::string(CATHBOX_SOURCE_DIR) + "/" + file;
  };
  if (!run_scripted(path(run.case_file), path(run.actions), trace, metrics, spec, setup)) return trace;
  std::printf("%s: %lld ticks; peak hand force %.1f mN at %.3f s; largest change %.1f mN/tick at %.3f s; "
              "%lld ticks change > 100 mN, %lld ticks |F| > 100 mN\n",
              run.name, static_cast<long long>(trace.ticks), trace.peak_mN, static_cast<double>(trace.peak_ms) * 1e-3,
              trace.max_jump_mN, static_cast<double>(trace.max_jump_ms) * 1e-3,
              static_cast<long long>(trace.ticks_over_slew), static_cast<long long>(trace.ticks_over_100mN));
  std::printf("  box-rendered: peak %.1f mN; largest change %.1f mN/tick at %.3f s; %lld ticks change > 100 mN; "
              "largest |rendered - own| %.1f mN at %.3f s; advanced with its catheter %lld ticks, %.1f mN at %.3f s\n",
              trace.rendered_peak_mN, trace.rendered_max_jump_mN, static_cast<double>(trace.rendered_max_jump_ms) * 1e-3,
              static_cast<long long>(trace.rendered_ticks_over_slew), trace.rendered_off_mN,
              static_cast<double>(trace.rendered_off_ms) * 1e-3, static_cast<long long>(trace.carried_ticks),
              trace.carried_off_mN, static_cast<double>(trace.carried_off_ms) * 1e-3);
  for (const ToolConvergence& c : metrics.convergence) {
    std::printf("  %-22s unconverged %.2f %% of %lld solved ticks\n", c.tool.c_str(), c.unconverged_pct(),
                static_cast<long long>(c.solved_ticks));
  }
  if (metrics.packing_density_pct) std::printf("  packing density %.2f %%\n", *metrics.packing_density_pct);
  return trace;
}

}  // namespace cathbox::session::test
