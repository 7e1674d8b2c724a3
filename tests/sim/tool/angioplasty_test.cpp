// Balloon angioplasty: the lumen the balloon leaves at the bundled ICA stenosis, over-sizing,
// and the widened wall swapped in at the same tick in both WallSwap modes (the swap's timing
// against a held builder: wall_swap_test.cpp).
// Virtual time only: no sleeps, no wall-clock assertions.
#include "tool/angioplasty.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <fstream>
#include <sstream>

#include "analytic_walls.hpp"
#include "state_fnv.hpp"
#include "tool/balloon.hpp"
#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"
#include "scenario/scenario_runner.hpp"
#include "vessel/hclm.hpp"

namespace cathbox::tool {
namespace {

vessel::VesselModel bundled_stenosis() {
  std::ifstream in(CATHBOX_SOURCE_DIR "/cases/neuro_stenosis.hclm");
  std::ostringstream text;
  text << in.rdbuf();
  vessel::HclmReadResult read = vessel::read_hclm(text.str(), "neuro_stenosis.hclm");
  EXPECT_TRUE(read.ok());
  return read.model;
}

// A balloon axis along a segment's centre line between two arc lengths.
std::vector<glm::dvec3> axis_along(const vessel::Segment& s, double from_mm, double to_mm) {
  std::vector<glm::dvec3> axis;
  double arc = 0.0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    if (i > 0) arc += glm::length(s.points[i].pos_mm - s.points[i - 1].pos_mm);
    if (arc >= from_mm && arc <= to_mm) axis.push_back(s.points[i].pos_mm);
  }
  return axis;
}

// The lesion's segment and its narrowest point's arc length.
double lesion_arc(const vessel::VesselModel& m, const Lesion& l) {
  const vessel::Segment& s = m.segments[l.segment];
  double arc = 0.0;
  for (std::size_t i = 1; i <= l.worst; ++i) arc += glm::length(s.points[i].pos_mm - s.points[i - 1].pos_mm);
  return arc;
}

// A semi-compliant 20 mm balloon (5.0 mm at its nominal 6 atm).
BalloonSpec balloon_5mm() {
  BalloonSpec b;
  b.length_mm = 20.0;
  b.from_tip_mm = 5.0;
  b.pressure_atm = {2.0, 6.0, 10.0, 14.0};
  b.diameter_mm = {4.6, 5.0, 5.3, 5.5};
  b.nominal_atm = 6.0;
  b.rated_burst_atm = 14.0;
  return b;
}

// Inflates to `atm` over the lesion (in 1 ms ticks, at the inflation device's rate), holds
// 5 s, deflates; returns the remodel.
LumenRemodel dilate(double atm, const LumenRemodelParams& params = {}) {
  const vessel::VesselModel model = bundled_stenosis();
  LumenRemodel lumen(model, params);
  const Lesion& l = lumen.lesion();
  const double c = lesion_arc(model, l);
  const std::vector<glm::dvec3> axis = axis_along(model.segments[l.segment], c - 10.0, c + 10.0);
  Balloon balloon(balloon_5mm(), 1.0);
  balloon.set_target_pressure(atm);
  for (int tick = 0; tick < 15000; ++tick) {
    if (tick == 10000) balloon.deflate();
    balloon.step(1e-3);
    lumen.apply({axis, balloon.diameter_mm(), balloon.inflated()});
  }
  EXPECT_FALSE(balloon.inflated());
  return lumen;
}

TEST(Angioplasty, FindsTheBundledIcaStenosis) {
  const vessel::VesselModel model = bundled_stenosis();
  const Lesion l = find_lesion(model);
  ASSERT_TRUE(l.found());
  EXPECT_EQ(model.segments[l.segment].name, "left_internal_carotid");
  // The generator narrows the ICA bulb by 70 % of its radius (src/neuro_case.cpp, sim/vessel).
  EXPECT_NEAR(stenosis_percent(model, l), 70.0, 3.0);
  EXPECT_NEAR(l.reference_diameter_mm, 5.6, 0.3);
  EXPECT_LT(l.first, l.worst);
  EXPECT_GT(l.last, l.worst);
}

TEST(Angioplasty, InflationAtTheBundledStenosisLeavesAtMost30PercentResidual) {
  const LumenRemodel lumen = dilate(8.0);
  EXPECT_GT(lumen.stenosis_before_percent(), 65.0);
  EXPECT_LE(lumen.stenosis_percent(), 30.0);
  RecordProperty("residual_stenosis_percent", std::to_string(lumen.stenosis_percent()));
  RecordProperty("stenosis_before_percent", std::to_string(lumen.stenosis_before_percent()));
  // Elastic recoil: less than the balloon's 5.15 mm at 8 atm gives (0 % against 5.6 mm would
  // mean no recoil at all; 1 - 5.15 / 5.6 = 8 % is the balloon's own diameter).
  EXPECT_GT(lumen.stenosis_percent(), 10.0);
  EXPECT_EQ(lumen.rupture_risk_events(), 0);
}

TEST(Angioplasty, FullRecoilGivesTheLesionBack) {
  LumenRemodelParams p;
  p.recoil = 1.0;
  const LumenRemodel lumen = dilate(8.0, p);
  EXPECT_NEAR(lumen.stenosis_percent(), lumen.stenosis_before_percent(), 1e-9);
}

TEST(Angioplasty, AnOversizedInflationIsARuptureRisk) {
  const vessel::VesselModel model = bundled_stenosis();
  LumenRemodel lumen(model);
  const Lesion& l = lumen.lesion();
  const double c = lesion_arc(model, l);
  const std::vector<glm::dvec3> axis = axis_along(model.segments[l.segment], c - 10.0, c + 10.0);
  const double ref = l.reference_diameter_mm;
  lumen.apply({axis, 1.0 * ref, true});
  EXPECT_EQ(lumen.rupture_risk_events(), 0);
  lumen.apply({axis, 1.2 * ref, true});
  lumen.apply({axis, 1.25 * ref, true});
  EXPECT_EQ(lumen.rupture_risk_events(), 1) << "one over-sized inflation counts once";
  lumen.apply({axis, 0.0, false});
  lumen.apply({axis, 1.2 * ref, true});
  EXPECT_EQ(lumen.rupture_risk_events(), 2);
  EXPECT_NEAR(lumen.max_oversize_ratio(), 1.25, 0.05);
}

// A remodelling balloon (balloon-assisted coiling) in a healthy parent artery: sized to the
// parent, the lumen keeps its radius (no new wall, no rupture risk); over-inflated, the lumen
// takes the chart's diameter at that pressure and no more, and after deflation keeps the
// model's (1 - recoil) of the gain (lumen_remodel.hpp: the gain is taken as plastic, as after
// angioplasty of a lesion).
TEST(Angioplasty, ARemodellingBalloonWidensAHealthyParentNoFurtherThanItsChart) {
  vessel::VesselModel healthy;
  healthy.segments.emplace_back();
  for (int i = 0; i <= 40; ++i) healthy.segments[0].points.push_back({{0.0, 0.0, 1.0 * i}, 2.0});  // a 4 mm parent
  BalloonSpec compliant;  // 4.0 mm at 2 atm, 5.0 mm at 4 atm
  compliant.length_mm = 10.0;
  compliant.pressure_atm = {1.0, 2.0, 4.0};
  compliant.diameter_mm = {3.0, 4.0, 5.0};
  compliant.nominal_atm = 2.0;
  compliant.rated_burst_atm = 4.0;
  const std::vector<glm::dvec3> axis = axis_along(healthy.segments[0], 15.0, 25.0);
  const auto widest = [](const vessel::VesselModel& m) {
    double r = 0.0;
    for (const vessel::CenterlinePoint& p : m.segments[0].points) r = std::max(r, p.radius_mm);
    return r;
  };
  const auto inflate = [&](LumenRemodel& lumen, double atm) {
    Balloon balloon(compliant, 0.9);
    balloon.set_target_pressure(atm);
    bool changed = false;
    for (int tick = 0; tick < 6000; ++tick) {
      if (tick == 4000) balloon.deflate();
      balloon.step(1e-3);
      changed |= lumen.apply({axis, balloon.diameter_mm(), balloon.inflated()});
      if (tick == 3999) {
        EXPECT_NEAR(widest(lumen.model()), std::max(2.0, 0.5 * balloon.diameter_at(atm)), 1e-12);
      }
    }
    return changed;
  };
  LumenRemodel sized(healthy);
  EXPECT_FALSE(inflate(sized, 2.0)) << "a balloon of the parent's size asked for a new wall";
  EXPECT_EQ(sized.model(), healthy);
  EXPECT_EQ(sized.rupture_risk_events(), 0);
  LumenRemodel over(healthy);
  EXPECT_TRUE(inflate(over, 4.0));
  EXPECT_EQ(over.rupture_risk_events(), 1);  // 5.0 / 4.0 = 1.25 > 1.1
  const LumenRemodelParams params;
  EXPECT_NEAR(widest(over.model()), 2.0 + (1.0 - params.recoil) * 0.5, 1e-12);
}

// An inflation counts once the balloon is unfolded: above 1 atm, or above its chart's first
// pressure if that is lower. A compliant remodelling balloon (its chart from 0.5 atm, that of
// tests/host/session/data/balloon_remodelling.case) held at 1 atm is up (it was counted as
// never inflated while its coils rested on it); the semi-compliant angioplasty balloon (its
// chart from 2 atm) at 1 atm is still folded, as before.
TEST(Angioplasty, AnInflationCountsOnceTheBalloonIsUnfoldedOnItsChart) {
  BalloonSpec remodelling;
  remodelling.length_mm = 10.0;
  remodelling.pressure_atm = {0.5, 1.0, 2.0, 3.0};
  remodelling.diameter_mm = {3.0, 4.0, 4.5, 4.8};
  remodelling.nominal_atm = 1.0;
  remodelling.rated_burst_atm = 3.0;
  const auto held = [](const BalloonSpec& spec, double atm) {
    Balloon balloon(spec, 0.9);
    balloon.set_target_pressure(atm);
    for (int tick = 0; tick < 2000; ++tick) balloon.step(1e-3);  // 1 s up, then held 1 s at atm
    balloon.deflate();
    for (int tick = 0; tick < 1000; ++tick) balloon.step(1e-3);
    return balloon;
  };
  const Balloon compliant = held(remodelling, 1.0);
  EXPECT_EQ(compliant.inflations(), 1);
  // Above 0.5 atm: from 0.25 s (2 atm/s up) to 0.05 s into the deflation (10 atm/s down).
  EXPECT_NEAR(compliant.inflated_time_s(), 2.0 - 0.25 + 0.05, 0.01);
  EXPECT_EQ(held(remodelling, 0.4).inflations(), 0);  // still folding out to its first point
  const Balloon angioplasty = held(balloon_5mm(), 1.0);
  EXPECT_EQ(angioplasty.inflations(), 0);
  EXPECT_EQ(held(balloon_5mm(), 6.0).inflations(), 1);
}

ToolSpec short_wire() {
  ToolSpec spec;
  spec.sections = {ToolSection{100.0, 0.36, 20.0, 15.0, 0.0}};
  return spec;
}

// Signed distance from a point to the wall (NaN when the wall is not within 10 mm).
double clearance_at(const WallModel& wall, const glm::dvec3& point_mm) {
  WallHint hint;
  WallContact c;
  WallProbe probe;
  probe.center_mm = point_mm;
  probe.range_mm = 10.0;
  return wall.probe(probe, hint, c) ? c.distance_mm : std::nan("");
}

// The real wall of the widened bundled stenosis, in both modes: the swap comes at the tick the
// simulation decided, the old tree answers with the narrow lumen until then, the new one with
// the wide lumen after, and both modes give the same wall.
TEST(Angioplasty, WidenedWallSwapsAtTheSameTickInBothModes) {
  const vessel::VesselModel model = bundled_stenosis();
  const Lesion lesion = find_lesion(model);
  const glm::dvec3 at = model.segments[lesion.segment].points[lesion.worst].pos_mm;
  const LumenRemodel widened = dilate(8.0);
  double clearance[2][2] = {};
  for (const WallSwap::Mode mode : {WallSwap::Mode::kSynchronous, WallSwap::Mode::kWorker}) {
    const int m = mode == WallSwap::Mode::kWorker ? 1 : 0;
    base::Result<std::unique_ptr<WallModel>> first = build_mesh_wall(model);
    ASSERT_TRUE(first) << first.error().message;
    WallSwap swap(std::move(*first), cached_mesh_wall_builder(), mode, 300);
    const std::vector<ToolSpec> tools{short_wire()};
    Simulator sim(swap.wall(), tools, Entry{{9.91, -28.32, -78}, {0, 0, 1}});
    const WallModel* old = &swap.wall();
    ASSERT_TRUE(swap.request(widened.model(), 0));
    if (mode == WallSwap::Mode::kWorker) swap.drain();  // the builder is done well before tick 300
    std::int64_t swapped_at = -1;
    for (int tick = 1; tick <= 400 && swapped_at < 0; ++tick) {
      if (tick == 299) {
        EXPECT_EQ(&sim.wall(), old);
        clearance[m][0] = clearance_at(sim.wall(), at);
      }
      sim.step(1e-3);
      if (swap.poll(sim, static_cast<std::int64_t>(sim.steps()))) swapped_at = static_cast<std::int64_t>(sim.steps());
    }
    EXPECT_EQ(swapped_at, 300);
    EXPECT_EQ(swap.waits(), 0u) << "built well before tick 300";
    clearance[m][1] = clearance_at(sim.wall(), at);
    EXPECT_LT(clearance[m][0], 1.0) << "the old wall: the 70 % stenosis (radius ~0.85 mm)";
    EXPECT_GT(clearance[m][1], 1.6) << "the new wall: the dilated lumen";
  }
  EXPECT_EQ(clearance[0][0], clearance[1][0]);
  EXPECT_EQ(clearance[0][1], clearance[1][1]);
}

// The bundled case played by its action script headless, as `cathbox sim run` plays it: the
// case's pass criteria (cases/neuro_angioplasty.case).
// The bundled case played by its script (synchronous wall swaps); `observe` sees every tick.
struct BundledRun {
  ScenarioResult result;
  std::size_t wire_segment = 0;
  std::uint64_t end_hash = 0;  // testing::state_fnv of the last tick
};
BundledRun run_bundled_case(std::function<void(const Simulator&)> observe = {}) {
  BundledRun run;
  const CaseParse c = load_case(CATHBOX_SOURCE_DIR "/cases/neuro_angioplasty.case");
  EXPECT_TRUE(c) << c.error().message;
  const ScriptParse script = load_script(CATHBOX_SOURCE_DIR "/cases/neuro_angioplasty.actions");
  EXPECT_TRUE(script) << script.error().message;
  if (!c || !script) return run;
  WorldBuild world = build_world(*c);
  EXPECT_TRUE(world) << world.error().message;
  if (!world || (*world)->source_model() == nullptr) return run;
  Angioplasty angio(*(*world)->source_model(), (*world)->release_wall(), WallSwap::Mode::kSynchronous);
  Simulator sim(angio.wall(), c->tools, (*world)->entry());
  ScenarioOptions options;
  options.every_ms = 1000;
  options.angioplasty = &angio;
  options.after_step = std::move(observe);
  std::ostringstream csv;
  run.result = run_scenario(sim, *script, options, csv);
  run.wire_segment = static_cast<std::size_t>(sim.tip_segment(sim.find_tool("guidewire")));
  run.end_hash = testing::state_fnv(sim);
  return run;
}

TEST(Angioplasty, TheBundledCaseMeetsItsPassCriteria) {
  const BundledRun run = run_bundled_case();
  const ScenarioResult& r = run.result;
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_TRUE(r.angioplasty.has_value());
  const AngioplastyFigures& f = *r.angioplasty;
  EXPECT_TRUE(f.lesion);
  EXPECT_GT(f.stenosis_before_percent, 65.0);
  EXPECT_LE(f.residual_stenosis_percent, 30.0);
  EXPECT_EQ(f.rupture_risk_events, 0);
  EXPECT_EQ(f.inflations, 1);
  EXPECT_GT(f.inflated_time_s, 10.0);
  EXPECT_NEAR(f.max_pressure_atm, 6.0, 1e-9);
  EXPECT_GE(f.wall_swaps, 1u);
  EXPECT_EQ(f.swap_waits, 0u);
  EXPECT_EQ(run.wire_segment, 20u) << "the wire stays across the lesion in the left ICA";
  RecordProperty("case_residual_stenosis_percent", std::to_string(f.residual_stenosis_percent));
  RecordProperty("case_wall_swaps", std::to_string(f.wall_swaps));
  std::printf("end-state hash %016llx, %llu wall swaps\n", static_cast<unsigned long long>(run.end_hash),
              static_cast<unsigned long long>(f.wall_swaps));
}

// In no tick of the bundled case does a wall contact of the balloon catheter read the contact
// cap (the penetration limit times the contact stiffness), i.e. a node the solve carried into
// the wall that limit_penetration clamped. Issue 16: its tip did so every ~5 ticks from 9.5 s.
// The wire's cap at the stenosis lip (a node wedged between two wall planes, held there at
// equilibrium) is a different cause and still open: counted and recorded, not asserted.
TEST(Angioplasty, TheBalloonCatheterNeverReachesTheContactCapInTheBundledCase) {
  const RodSettings settings;  // the simulator's defaults
  std::vector<std::size_t> capped_ticks;
  std::vector<double> peak_ratio;
  std::vector<std::string> names;
  std::int64_t tick = 0;
  std::int64_t first_capped_ms = -1;
  const BundledRun run = run_bundled_case([&](const Simulator& sim) {
    ++tick;
    capped_ticks.resize(sim.tool_count(), 0);
    peak_ratio.resize(sim.tool_count(), 0.0);
    names.resize(sim.tool_count());
    for (std::size_t t = 0; t < sim.tool_count(); ++t) {
      const Rod& rod = sim.rod(t);
      names[t] = rod.spec().name;
      double worst = 0.0;
      for (const RodContact& c : rod.contacts()) {
        const double cap = settings.contact_stiffness_mN_per_mm * settings.max_penetration_ratio * rod.node_radius_mm(c.node);
        worst = std::max(worst, c.normal_force_mN / cap);
      }
      peak_ratio[t] = std::max(peak_ratio[t], worst);
      if (worst > 0.999) {
        ++capped_ticks[t];
        if (names[t] == "balloon" && first_capped_ms < 0) first_capped_ms = tick;
      }
    }
  });
  ASSERT_TRUE(run.result.ok) << run.result.error;
  const auto balloon = std::find(names.begin(), names.end(), "balloon");
  ASSERT_NE(balloon, names.end());
  const auto b = static_cast<std::size_t>(balloon - names.begin());
  EXPECT_EQ(capped_ticks[b], 0u) << "first at " << first_capped_ms << " ms";
  EXPECT_LT(peak_ratio[b], 0.999);
  EXPECT_GT(peak_ratio[b], 0.0) << "the catheter touches the wall";
  for (std::size_t t = 0; t < names.size(); ++t) {
    RecordProperty("peak_contact_over_cap_" + names[t], std::to_string(peak_ratio[t]));
    RecordProperty("capped_ticks_" + names[t], std::to_string(capped_ticks[t]));
  }
}

}  // namespace
}  // namespace cathbox::tool
