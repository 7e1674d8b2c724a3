// The force the trainee's hand gets, tick by tick, in every bundled case that has a script, in a
// wire pushed into a dead end, and in a run into a bend that no other test or setting was tuned
// on (tests/host/session/data): each as a session in virtual time, as `cathbox session run
// --virtual` runs it. Three checks, each with its own meaning (docs/sim-tool/convergence.md,
// "What the hand-force replays check"):
//
// 1. HandForceReplay (the bundled runs, the held-out bend): the held tool's own hand force, as
//    the simulation gives it, within the box's 5 N full scale and 100 mN per 1 ms tick slew: a
//    tool pushed by a hand at <= 30 mm/s against walls of finite stiffness asks for nothing the
//    box cannot give. Every tool's unconverged share (`unconverged_pct`) <= 0.5 %.
// 2. DeadEndRendering.TheBoxRendersWithinItsFullScaleAndSlew: past a dead end the wire's own force
//    is physically over 5 N (check 3), so what must stay within the box's limits there is what
//    the box renders: the held tool's law shaped by session::PassiveLaw exactly as BoxHand
//    shapes it (passive_law.hpp), the box's output (ShapedLaw::output_mN) read at the hand's
//    position and speed each tick and fed back as the next tick's readback.
// 3. DeadEndHelix.TheWiresOwnForceFollowsLubinskisHelixWithConvergedSteps: the wire's own force
//    at the end of the push against helical buckling in the run's geometry (Lubinski, Althouse
//    & Logan 1962; with wall friction while pushing in, Mitchell 1986), and every tool's
//    unconverged share <= 0.5 %.
//
// The held tool's force is compared between consecutive ticks while the hand holds the same
// tool (a select or a coil loaded at the hub starts afresh: another device in the hand).
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "session/action_script_hand.hpp"
#include "session/control.hpp"
#include "session/passive_law.hpp"
#include "session/session.hpp"

namespace cathbox::session {
namespace {

constexpr double kFullScale_mN = 5000.0;       // the box's insertion full scale
constexpr double kSlewPerTick_mN = 100.0;      // the box's slew limit per 1 ms tick
constexpr double kUnconvergedMax_pct = 0.5;    // issue 29: every tool converges on ≥ 99.5 % of ticks
constexpr double kRounding_mN = 1e-6;          // a slew step met exactly, less its rounding

struct FeelRun {
  const char* name;
  const char* case_file;  // relative to the source tree
  const char* actions;
};

// Per tick: the held tool's hand force and its change since the last tick with the same tool.
class HandForceTrace : public TickObserver {
 public:
  void observe(const TickView& v) override {
    const double f = v.snapshot.tools[v.input.held].hand_force_mN;
    bool fresh = !started_ || v.input.held != held_;
    for (const Control& c : v.controls) {
      if (c.kind == static_cast<std::uint16_t>(ControlKind::kLoadCoil)) fresh = true;
    }
    render(v, fresh);
    if (!fresh) {
      const double jump = std::abs(f - last_mN_);
      if (jump > max_jump_mN) {
        max_jump_mN = jump;
        max_jump_ms = v.time_us / 1000;
      }
      if (jump > kSlewPerTick_mN) ++ticks_over_slew;
    }
    if (std::abs(f) > peak_mN) {
      peak_mN = std::abs(f);
      peak_ms = v.time_us / 1000;
    }
    if (std::abs(f) > kSlewPerTick_mN) ++ticks_over_100mN;
    // The solver's own word, per rod (the case's tools, then the released coils), to check the
    // metrics' unconverged shares against.
    const std::size_t tools = v.sim.tool_count();
    const std::size_t rods = tools + v.sim.detached_count();
    unconverged.resize(rods, 0);
    solved.resize(rods, 0);
    for (std::size_t t = 0; t < rods; ++t) {
      const tool::Rod& rod = t < tools ? v.sim.rod(t) : v.sim.detached(t - tools);
      if (rod.first_free_node() >= rod.node_total()) continue;
      ++solved[t];
      if (!rod.converged()) ++unconverged[t];
    }
    started_ = true;
    held_ = v.input.held;
    last_mN_ = f;
    ++ticks;
  }
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
  // The held tool's own force on the last tick the hand pushed in (the end of the push).
  double pushed_force_mN = 0.0;
  double pushed_to_mm = 0.0;

 private:
  // BoxHand::feel's path (box_hand.cpp): the law to the box's frame (here the session's: the
  // scripted hand has no count origin, and a translation changes no force), shaped with the box's
  // readback, which an ideal box reports as the output it rendered at the hand's position and
  // speed. The limits are PassiveLawLimits' defaults, the emulated box's (5 N, 100 mN/ms, 1 ms).
  void render(const TickView& v, bool fresh) {
    const double x = static_cast<double>(v.input.tools[v.input.held].insertion_um) * 1e-3;
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
      }
    }
    rendered_peak_mN = std::max(rendered_peak_mN, std::abs(out));
    readback_ = {out, speed};
    rendered_mN_ = -out;
    hand_mm_ = x;
    time_us_ = v.time_us;
  }
  PassiveLaw box_law_;
  BoxReadback readback_;
  double rendered_mN_ = 0.0;
  double hand_mm_ = 0.0;
  std::int64_t time_us_ = 0;

  bool started_ = false;
  std::size_t held_ = 0;
  double last_mN_ = 0.0;
};

// Runs a case with its script as a session in virtual time, to its end; prints the figures.
// Every tool's unconverged share within issue 29's bound.
void expect_every_tool_converged(const Metrics& m) {
  for (const ToolConvergence& c : m.convergence) EXPECT_LE(c.unconverged_pct(), kUnconvergedMax_pct) << c.tool;
}

HandForceTrace run_session(const FeelRun& run, Metrics& metrics, tool::Case* spec = nullptr) {
  HandForceTrace trace;
  const std::string root = std::string(CATHBOX_SOURCE_DIR) + "/";
  SessionCaseLoad loaded = load_session_case(root + run.case_file);
  EXPECT_TRUE(loaded) << loaded.error().message;
  if (!loaded) return trace;
  if (spec != nullptr) *spec = loaded.value()->spec;
  std::string error;
  auto script = ActionScriptHand::load(root + run.actions, *loaded.value());
  EXPECT_TRUE(script) << (script ? "" : script.error().message);
  if (!script) return trace;
  auto hand = std::move(*script);
  Session s(std::move(loaded.value()), std::move(hand));
  s.add_observer(trace);
  while (!s.over() && s.step_virtual(1000) > 0) {
  }
  metrics = s.metrics();
  std::printf("%s: %lld ticks; peak hand force %.1f mN at %.3f s; largest change %.1f mN/tick at %.3f s; "
              "%lld ticks change > 100 mN, %lld ticks |F| > 100 mN\n",
              run.name, static_cast<long long>(trace.ticks), trace.peak_mN, static_cast<double>(trace.peak_ms) * 1e-3,
              trace.max_jump_mN, static_cast<double>(trace.max_jump_ms) * 1e-3,
              static_cast<long long>(trace.ticks_over_slew), static_cast<long long>(trace.ticks_over_100mN));
  std::printf("  box-rendered: peak %.1f mN; largest change %.1f mN/tick at %.3f s; %lld ticks change > 100 mN\n",
              trace.rendered_peak_mN, trace.rendered_max_jump_mN, static_cast<double>(trace.rendered_max_jump_ms) * 1e-3,
              static_cast<long long>(trace.rendered_ticks_over_slew));
  for (const ToolConvergence& c : metrics.convergence) {
    std::printf("  %-22s unconverged %.2f %% of %lld solved ticks\n", c.tool.c_str(), c.unconverged_pct(),
                static_cast<long long>(c.solved_ticks));
  }
  if (metrics.packing_density_pct) std::printf("  packing density %.2f %%\n", *metrics.packing_density_pct);
  return trace;
}

const FeelRun kRuns[] = {
    {"y_bifurcation_left", "cases/y_bifurcation.case", "cases/y_bifurcation_left.actions"},
    {"neuro_angioplasty", "cases/neuro_angioplasty.case", "cases/neuro_angioplasty.actions"},
    {"neuro_coiling", "cases/neuro_coiling.case", "cases/neuro_coiling.actions"},
    {"dead_end", "tests/host/session/data/dead_end.case", "tests/host/session/data/dead_end.actions"},
    {"held_out_bend", "tests/host/session/data/held_out_bend.case", "tests/host/session/data/held_out_bend.actions"},
    {"dead_end_compliant", "tests/host/session/data/dead_end_compliant.case", "tests/host/session/data/dead_end.actions"},
};

// Every run's figures, and the metrics' own: the peak hand force is the trace's, each tool's
// unconverged share is the solver's count (Rod::converged() over the ticks it had free nodes).
TEST(HandForceFigures, MetricsReportTheHandsPeakAndEachToolsUnconvergedShare) {
  for (const FeelRun& run : kRuns) {
    Metrics m;
    const HandForceTrace trace = run_session(run, m);
    ASSERT_GT(trace.ticks, 1000) << run.name;
    EXPECT_DOUBLE_EQ(m.peak_hand_force_mN, trace.peak_mN) << run.name;
    ASSERT_EQ(m.convergence.size(), trace.solved.size()) << run.name;
    double largest = 0.0;
    for (std::size_t t = 0; t < trace.solved.size(); ++t) {
      EXPECT_EQ(m.convergence[t].solved_ticks, trace.solved[t]) << run.name << " " << m.convergence[t].tool;
      EXPECT_EQ(m.convergence[t].unconverged_ticks, trace.unconverged[t]) << run.name << " " << m.convergence[t].tool;
      largest = std::max(largest, m.convergence[t].unconverged_pct());
    }
    EXPECT_EQ(m.unconverged_pct_max(), largest);
  }
}

// Check 1, the bounds of issue 29 ("the feel") on the tool's own force. Met by the Y bifurcation,
// the angioplasty and the held-out bend; the coiling run is instantiated disabled (run it with
// --gtest_also_run_disabled_tests) until its tools converge; the dead ends have checks 2 and 3
// instead (their wire's own force is physically over 5 N). Figures: docs/sim-tool/convergence.md
// (HandForceFigures prints them). The angioplasty met them once the wire's clamp at the balloon
// catheter's tip pushed back on that tip (Simulator::push_on_carrier_tip) and the predictor
// stopped putting the catheter's tip on the wire's chord behind its entry (Rod::point_at_from_tip):
// balloon unconverged 2.03 -> 0.01 %, guidewire 0.25 -> 0.16 %, peak 172 -> 53 mN, largest change
// 92 -> 80 mN/tick. The held-out bend met them once the wall's stick spring was the tissue's shear
// stiffness under the wire (Mindlin; 246 mN/mm) instead of a tenth of the rigid wall's penalty
// (2·10⁴ mN/mm): unconverged 0.89 -> 0.13 %, largest change 134.5 -> 57.3 mN/tick at the pull-back.
class HandForceReplay : public ::testing::TestWithParam<FeelRun> {};

TEST_P(HandForceReplay, StaysWithinTheBoxsSlewAndFullScaleWithConvergedSteps) {
  const FeelRun& run = GetParam();
  Metrics m;
  const HandForceTrace trace = run_session(run, m);
  ASSERT_GT(trace.ticks, 1000);
  EXPECT_LE(trace.peak_mN, kFullScale_mN) << "at " << trace.peak_ms << " ms";
  EXPECT_LE(trace.max_jump_mN, kSlewPerTick_mN) << "at " << trace.max_jump_ms << " ms";
  EXPECT_EQ(trace.ticks_over_slew, 0);
  expect_every_tool_converged(m);
}

std::string run_name(const ::testing::TestParamInfo<FeelRun>& info) { return info.param.name; }

INSTANTIATE_TEST_SUITE_P(Meets, HandForceReplay, ::testing::Values(kRuns[0], kRuns[1], kRuns[4]), run_name);
INSTANTIATE_TEST_SUITE_P(DISABLED_NotYet, HandForceReplay, ::testing::Values(kRuns[2]), run_name);

// Helical buckling of the dead end's wire, from its case: one tube of radius R closed at its far
// end by a round cap, the entry on its axis; the wire's shaft (its proximal section: EI, diameter
// d) and its softer distal sections (total length s), wall friction mu.
//   L = entry to the cap's pole less the wire's radius (where the tip meets the end),
//   r = R - d/2 (the helix's radius), delta = insertion - L - s: the soft tip (EI <= 3 N mm^2,
//   Euler load of tens of mN over its 50 mm) folds back at the closed end beside the shaft and
//   takes up its own length (the rigid run at 260 mm: the fold at 200.2 mm, the tip back at
//   152.8 mm), the shaft the rest.
// Lubinski, Althouse & Logan, J. Petroleum Technology 14(6), 1962: F = 8 pi^2 EI / p^2 and the
// strain (2 pi r / p)^2 / 2 = r^2 F / (4 EI), so frictionless F = 4 EI delta / (r^2 L)
// (sim/tool's RodValidation.WirePushedIntoAClosedTubeBucklesIntoLubinskisHelix checks the rod
// against it: +5, -5 %, its stiffness -14 %). Pushed in with wall friction, the normal force per
// length r F^2 / (4 EI) makes dF/ds = mu r F^2 / (4 EI) along the wire; integrating the strain
// over L gives the hand's force F = 4 EI / (mu r L) (exp(mu delta / r) - 1) (Mitchell,
// "Frictional forces in helical buckling of tubing", SPE Drilling Engineering 1(6), 1986),
// which tends to the frictionless line as mu -> 0. A planar (sinusoidal) buckle of amplitude r
// has the same strain-force relation, r^2 F / (4 EI), to the same order.
struct HelixPrediction {
  double shaft_ei_mNmm2 = 0.0, clearance_mm = 0.0, length_mm = 0.0, delta_mm = 0.0, friction = 0.0;
  double frictionless_mN = 0.0, pushing_mN = 0.0;
};

HelixPrediction lubinski(const tool::Case& spec, double insertion_mm) {
  HelixPrediction h;
  const tool::ToolSpec& wire = spec.tools.at(0);
  const auto& tube = spec.tubes.at(0);
  const glm::dvec3 entry = spec.entry ? spec.entry->point_mm : glm::dvec3(0.0);
  const double wire_radius_mm = wire.sections.front().outer_diameter_mm / 2.0;
  h.shaft_ei_mNmm2 = wire.sections.front().bending_stiffness_Nmm2 * 1000.0;
  h.clearance_mm = tube.radius_b_mm - wire_radius_mm;
  h.length_mm = glm::length(tube.b_mm - entry) + tube.radius_b_mm - wire_radius_mm;
  double soft_mm = 0.0;
  for (std::size_t k = 1; k < wire.sections.size(); ++k) soft_mm += wire.sections[k].length_mm;
  h.delta_mm = insertion_mm - h.length_mm - soft_mm;
  h.friction = wire.friction;
  const double r2l = h.clearance_mm * h.clearance_mm * h.length_mm;
  h.frictionless_mN = 4.0 * h.shaft_ei_mNmm2 * h.delta_mm / r2l;
  const double mu_r_l = h.friction * h.clearance_mm * h.length_mm;
  h.pushing_mN = h.friction > 0.0 ? 4.0 * h.shaft_ei_mNmm2 / mu_r_l * std::expm1(h.friction * h.delta_mm / h.clearance_mm)
                                   : h.frictionless_mN;
  return h;
}

// The dead ends: the box's limits on what it renders (check 2).
class DeadEndRendering : public ::testing::TestWithParam<FeelRun> {};

TEST_P(DeadEndRendering, TheBoxRendersWithinItsFullScaleAndSlew) {
  const FeelRun& run = GetParam();
  Metrics m;
  const HandForceTrace trace = run_session(run, m);
  ASSERT_GT(trace.ticks, 1000);
  EXPECT_LE(trace.rendered_peak_mN, kFullScale_mN + kRounding_mN);
  EXPECT_LE(trace.rendered_max_jump_mN, kSlewPerTick_mN + kRounding_mN) << "at " << trace.rendered_max_jump_ms << " ms";
  EXPECT_EQ(trace.rendered_ticks_over_slew, 0);
  // Not vacuous: the wire's own force is over the full scale there, and changes by more.
  EXPECT_GT(trace.peak_mN, 0.5 * kFullScale_mN);
}

INSTANTIATE_TEST_SUITE_P(Meets, DeadEndRendering, ::testing::Values(kRuns[3], kRuns[5]), run_name);

// Every tool's step converges on >= 99.5 % of its ticks (issue 29), in the runs whose hand force
// has its own checks elsewhere: the dead ends (checks 2 and 3) and the coiling run (check 1 not
// yet met). A tick that ends unconverged is solved again in 2, then 4 sub-increments of the
// hand's motion (RodSettings::substeps_max, lone tools only): dead end 2.41 -> 0.29 %, compliant
// 1.59 -> 0.02 %. The coiling run is instantiated disabled (run it with
// --gtest_also_run_disabled_tests) until its nested tools converge: microcatheter / microwire /
// coil 1.47 / 6.43 / 4.42 % (docs/sim-tool/convergence.md, "Sub-stepped ticks").
class ToolConvergence : public ::testing::TestWithParam<FeelRun> {};

TEST_P(ToolConvergence, EveryToolConvergesOnAtLeast99Point5PercentOfItsTicks) {
  const FeelRun& run = GetParam();
  Metrics m;
  const HandForceTrace trace = run_session(run, m);
  ASSERT_GT(trace.ticks, 1000);
  ASSERT_FALSE(m.convergence.empty());
  expect_every_tool_converged(m);
}

INSTANTIATE_TEST_SUITE_P(Meets, ToolConvergence, ::testing::Values(kRuns[3], kRuns[5]), run_name);
INSTANTIATE_TEST_SUITE_P(DISABLED_NotYet, ToolConvergence, ::testing::Values(kRuns[2]), run_name);

// The dead ends: the wire's own force against its helix, with every step converged (check 3).
// The tolerance: the rod's own agreement with Lubinski's frictionless helix (15 %, sim/tool's
// helical buckling test) on either side of the band between the frictionless line (the least a
// wire pushed in can read) and Mitchell's friction (the most, every contact slipping at mu N).
class DeadEndHelix : public ::testing::TestWithParam<FeelRun> {};

TEST_P(DeadEndHelix, TheWiresOwnForceFollowsLubinskisHelixWithConvergedSteps) {
  constexpr double kTolerance = 0.15;
  const FeelRun& run = GetParam();
  Metrics m;
  tool::Case spec;
  const HandForceTrace trace = run_session(run, m, &spec);
  ASSERT_GT(trace.ticks, 1000);
  const HelixPrediction h = lubinski(spec, trace.pushed_to_mm);
  std::printf("  pushed to %.2f mm: the shaft %.2f mm past the end (L %.1f mm, r %.2f mm, EI %.0f N mm^2, mu %.2f): "
              "own force %.0f mN, Lubinski %.0f mN frictionless, %.0f mN pushed with friction (Mitchell)\n",
              trace.pushed_to_mm, h.delta_mm, h.length_mm, h.clearance_mm, h.shaft_ei_mNmm2 * 1e-3, h.friction,
              trace.pushed_force_mN, h.frictionless_mN, h.pushing_mN);
  ASSERT_GT(h.delta_mm, 0.0) << "the script does not push the shaft past the end";
  EXPECT_GE(trace.pushed_force_mN, (1.0 - kTolerance) * h.frictionless_mN);
  EXPECT_LE(trace.pushed_force_mN, (1.0 + kTolerance) * h.pushing_mN);
  expect_every_tool_converged(m);
}

// Not met yet (docs/sim-tool/convergence.md, "What the hand-force replays check"): the wire reads
// 3.5 (rigid) and 1.7 (compliant) times the band's top at 260 mm, buckled in one plane, and
// its steps now converge (0.29 / 0.02 % unconverged, ToolConvergence).
INSTANTIATE_TEST_SUITE_P(DISABLED_NotYet, DeadEndHelix, ::testing::Values(kRuns[3], kRuns[5]), run_name);

}  // namespace
}  // namespace cathbox::session
