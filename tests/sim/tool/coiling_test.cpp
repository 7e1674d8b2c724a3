// Coiling in the bundled cases, in virtual time: the triaxial stack of cases/neuro_coiling.case
// reaches the aneurysm neck by its action file and deploys and detaches the coil; a second coil
// packs against the first in the bundled sac; the dense sequence detaches each coil before the
// next. (The free sphere: coil_in_sphere_test.cpp and coil_deploy_test.cpp.)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"
#include "scenario/script_player.hpp"
#include "state_fnv.hpp"
#include "tool/aneurysm_sac.hpp"
#include "tool/coil_metrics.hpp"
#include "tool/simulator.hpp"

#include "coil_test_support.hpp"

namespace cathbox::tool {
namespace {

using namespace testing;  // coil_test_support.hpp: the sphere, the tools, drive and the packing checks

// The triaxial stack of the bundled coiling case, driven by its action file as `cathbox sim
// run` drives it: from the guide in the right ICA the microcatheter reaches the neck of the
// right MCA aneurysm over the microwire, the framing coil deploys into the sac and is detached
// there; `load_coil` then feeds the case's next coil (40 mm, 4 mm loops) into the same
// microcatheter on a new pusher, and it packs against the first: every node of both in the sac
// (none past the neck plane, none out of the lumen by more than 10 % of its radius), no
// herniation, the coils touching without crossing, overlap <= 10 % of the coil diameter at
// every step of the second coil, the packing density the sum of both coils' volumes.
TEST(Coiling, TriaxialStackReachesTheAneurysmNeckByTheScriptedActionFile) {
  const std::string dir = std::string(CATHBOX_SOURCE_DIR) + "/cases/";
  CaseParse c = load_case(dir + "neuro_coiling.case");
  ASSERT_TRUE(c) << c.error().message;
  ScriptParse script = load_script(dir + "neuro_coiling.actions");
  ASSERT_TRUE(script) << script.error().message;
  WorldBuild world = build_world(*c);
  ASSERT_TRUE(world) << world.error().message;
  ASSERT_TRUE((*world)->sac());
  const AneurysmSac& sac = *(*world)->sac();
  // The right side (the patient's right is -x): the sac, the case's target and the entry.
  const vessel::VesselModel& model = *(*world)->model();
  EXPECT_EQ(model.segments[*model.index_of(sac.segment)].name, "right_mca_aneurysm");
  ASSERT_TRUE(c->target);
  EXPECT_EQ(c->target->segment, sac.segment);
  EXPECT_LT(sac.neck_centre_mm.x, -25.0);
  EXPECT_LT((*world)->entry().point_mm.x, -20.0);
  Simulator sim((*world)->wall(), c->tools, (*world)->entry());
  const std::size_t micro = sim.find_tool("microcatheter"), coil = sim.find_tool("coil");
  ASSERT_LT(micro, sim.tool_count());
  ASSERT_LT(coil, sim.tool_count());
  ASSERT_EQ(sim.outer_of(micro), sim.find_tool("guide"));
  ASSERT_EQ(sim.outer_of(sim.find_tool("microwire")), micro);
  ASSERT_EQ(sim.outer_of(coil), micro);
  EXPECT_EQ(c->tools[coil].sections.back().shape, CoilShape::kHelix);
  EXPECT_EQ(c->tools[coil].sections.back().loop_diameter_mm, 5.0);
  ASSERT_EQ(c->tools[coil].next_coils.size(), 1u);
  const double second_mm = c->tools[coil].next_coils[0].length_mm;
  std::vector<ScriptPlayer::ToolInfo> infos;
  for (const ToolSpec& t : c->tools) infos.push_back(tool_info(t));
  base::Result<ScriptPlayer> player = ScriptPlayer::make(*script, infos, 0, "neuro_coiling.actions");
  ASSERT_TRUE(player) << player.error().message;
  CoilMetrics metrics(sim, sac);
  double micro_best_depth = -1e9;
  std::optional<double> depth_at_deploy;
  double shallowest_deploying = 1e9;  // the microcatheter tip's depth while a coil goes out
  bool detached = false;
  WorstOverlap second_overlap;  // while the second coil is out
  double pusher_peak_mN = 0.0;  // the coil tool's hand force after a detach, pusher alone
  // While a detachment zone parts (detach command to release, Simulator::advance_partings): the
  // coil tool's largest change of hand force a tick, and each parting's length in ticks.
  double parting_change_mN = 0.0, last_hand_mN = 0.0;
  std::vector<int> parting_ticks;
  for (std::int64_t now = 0; now < 200'000; ++now) {
    const ScriptPlayer::Step step = player->advance(now);
    if (step.selected) sim.select(*step.selected);
    if (step.ended) break;
    if (step.detach) {
      ASSERT_EQ(sim.detach(*step.detach), DeviceError::kNone) << "at " << now << " ms";
      detached = true;
      parting_ticks.push_back(0);
    }
    const bool was_parting = sim.parting(coil);
    if (step.load_coil) {
      ASSERT_EQ(sim.load_next_coil(*step.load_coil), DeviceError::kNone) << "at " << now << " ms";
    }
    for (std::size_t t = 0; t < sim.tool_count(); ++t) {
      sim.set_insertion(t, player->insertion_mm(t));
      sim.set_rotation(t, player->rotation_rad(t));
    }
    sim.step();
    metrics.observe(sim);
    if (was_parting) {
      parting_change_mN = std::max(parting_change_mN, std::abs(sim.hand_force_mN(coil) - last_hand_mN));
      ++parting_ticks.back();
    }
    last_hand_mN = sim.hand_force_mN(coil);
    if (sim.released_mm(coil) > 0.0) pusher_peak_mN = std::max(pusher_peak_mN, std::abs(sim.hand_force_mN(coil)));
    const glm::dvec3 tip = sim.tip(micro).position_mm;
    if (glm::length(tip - sac.neck_centre_mm) < sac.neck_radius_mm + sac.dome_radius_mm) {
      micro_best_depth = std::max(micro_best_depth, sac.depth_mm(tip));
    }
    if (!depth_at_deploy && metrics.figures().deployed_mm > 0.0) depth_at_deploy = sac.depth_mm(tip);
    if (CoilMetrics::attached_deployed_mm(sim, coil) > 0.0) shallowest_deploying = std::min(shallowest_deploying, sac.depth_mm(tip));
    if (sim.coils_loaded(coil) == 1) {
      const RodContactField::Overlap o = sim.worst_coil_overlap();
      if (o.diameter_mm > 0.0 && o.depth_mm / o.diameter_mm > second_overlap.fraction) {
        second_overlap.fraction = o.depth_mm / o.diameter_mm;
        second_overlap.at_mm = metrics.figures().deployed_mm - c->tools[coil].detach_mm;
      }
      if (sim.detached_count() == 1) {
        second_overlap.closest_mm = std::min(second_overlap.closest_mm, closest_to_first_released(sim, coil));
      }
    }
    if (player->settled(now, 100)) break;
  }
  // The microcatheter's tip came to the neck (within half a millimetre of its plane, or past it).
  EXPECT_GT(micro_best_depth, -0.5) << "closest approach to the neck plane " << micro_best_depth << " mm";
  ASSERT_TRUE(depth_at_deploy);
  EXPECT_GT(*depth_at_deploy, -0.5);
  EXPECT_TRUE(detached);
  EXPECT_EQ(sim.coils_loaded(coil), 1u);
  ASSERT_EQ(sim.detached_count(), 2u);
  const double total = c->tools[coil].detach_mm + second_mm;
  EXPECT_NEAR(metrics.figures().deployed_mm, total, 0.6);
  // Packing density: the sum of both coils' analytic volumes over the sac.
  EXPECT_NEAR(metrics.figures().packing_density, 0.25 * std::acos(-1.0) * kCoilOd * kCoilOd * total / sac.volume_mm3, 1e-3);
  EXPECT_EQ(metrics.figures().herniations, 0);
  // The microcatheter stays in the sac while each coil goes out, and its kick-back is within the
  // case's criterion: its tip is placed ~2.2 mm past the neck and climbs to ~4 mm past it while
  // each pusher is drawn back (the pusher's pull on the catheter's turns), and the next coil's
  // push takes it back from there (3.30 mm; docs/sim-tool/coiling.md, "The coil's push on its
  // catheter's turns").
  EXPECT_GT(shallowest_deploying, 0.0);
  EXPECT_LT(metrics.figures().kick_back_mm, 4.0);
  std::printf("microcatheter tip while a coil goes out: at least %.2f mm past the neck\n", shallowest_deploying);
  expect_in_the_sac(sim, sac, (*world)->wall());
  expect_packed_apart(sim, second_overlap);
  // After a detach the pusher alone (the coil's stiff axial springs, out of the rod-contact
  // field) reads its hand force at the linearised equilibrium: 1 um of residual read as
  // 3·10^5-1.6·10^6 mN before; 17-31 N while the script pushed the detachment zone 1.5 mm out
  // of a microcatheter tip lying on the sac wall (1.17 N at 0.1 mm, drawn back): the bound
  // catches the reading, not that.
  EXPECT_LT(pusher_peak_mN, 5.0e4);
  std::printf("pusher after detach: peak %.0f mN\n", pusher_peak_mN);
  // The zone parts over 0.1 s at rest, and the hand feels the push it held leave within the box's
  // slew (100 mN a 1 ms tick; released in one tick, -276.9 and -233.5 mN: hand_force_jumps_test.cpp).
  ASSERT_EQ(parting_ticks.size(), 2u);
  for (const int ticks : parting_ticks) EXPECT_EQ(ticks, 100);
  EXPECT_LT(parting_change_mN, 100.0);
  std::printf("detachment zones parting: %d and %d ticks, the coil tool's hand force changing by %.1f mN a tick at most\n",
              parting_ticks[0], parting_ticks[1], parting_change_mN);
  std::printf("two coils: %.1f mm deployed, packing %.2f %% of %.1f mm3, %d herniations, kick-back %.2f mm, "
              "second coil's deepest overlap %.1f %% of the diameter, closest to the first %.2f mm while pushed\n",
              metrics.figures().deployed_mm, 100.0 * metrics.figures().packing_density, sac.volume_mm3,
              metrics.figures().herniations, metrics.figures().kick_back_mm, 100.0 * second_overlap.fraction,
              second_overlap.closest_mm);
  // Each release's push on the coil (CoilMetrics' detach force), printed: the bundled script detaches
  // at rest with the hand still at its markers; in neutral since the coil's push reacts on the
  // microcatheter's turns (record format 30: +9.4, +10.0 mN), under tension before (~200 mN:
  // docs/sim-tool/convergence.md, "Detaching in neutral").
  const CoilFigures& f = metrics.figures();
  ASSERT_EQ(f.detachments, 2);
  std::printf("detach force: %+.1f, %+.1f mN (%d under tension)\n", f.detach_force_mN[0], f.detach_force_mN[1],
              f.detached_under_tension);
  // The end state, bit for bit: the same build gives the same hash alone or beside any load.
  std::printf("end-state hash %016llx after %llu steps\n", static_cast<unsigned long long>(testing::state_fnv(sim)),
              static_cast<unsigned long long>(sim.steps()));
}

// Later coils pack against earlier ones in the bundled sac (the bundled coiling case holds 4
// tools, its triaxial stack and one coil, so this runs beside it): the microcatheter parked in
// the right M1 with its tip ~2 mm past the neck of right_mca_aneurysm, a 60 mm framing coil (5 mm
// loops) pushed out at 8 mm/s and detached, its pusher drawn back, then a 40 mm filling coil (4
// mm loops) pushed out against it and detached. Every node of both stays in the sac (none past
// the neck plane into the M1, none out of the lumen by more than 10 % of its radius), no
// herniation; the second touches the first without passing through it or itself.
TEST(Coiling, SecondCoilPacksAgainstTheFirstInTheBundledSac) {
  constexpr std::string_view kCase = R"(cathbox-case 1
name two coils in the right MCA aneurysm, microcatheter parked in the M1
vessel neuro_aneurysm.hclm
entry -19.09 15.71 236.58  -0.981 0.038 0.189
tool microcatheter catheter
  section 1500 od=0.7 ei=1 gj=0.8
  friction 0.1
  inner_diameter 0.43
  spacing 2 0.5 40
end
)";
  // A 10-system coil on its pusher (as in cases/neuro_coiling.case), LENGTH mm of LOOP mm loops.
  const auto coil = [](const std::string& name, int length, int loop) {
    return "tool " + name + " coil\n  section 1800 od=0.33 ei=10 gj=8\n  section " + std::to_string(length) +
           " od=0.25 ei=0.02 gj=0.016 shape=helix loop=" + std::to_string(loop) + "\n  friction 0.05\n  detach " +
           std::to_string(length) + "\n  inside microcatheter\n  spacing 2 0.5 " + std::to_string(length + 2) + "\nend\n";
  };
  CaseParse c = parse_case(std::string(kCase) + coil("coil", 60, 5) + coil("coil2", 40, 4),
                           std::string(CATHBOX_SOURCE_DIR) + "/cases/two_coils.case");
  ASSERT_TRUE(c) << c.error().message;
  WorldBuild world = build_world(*c);
  ASSERT_TRUE(world) << world.error().message;
  ASSERT_TRUE((*world)->sac());
  const AneurysmSac& sac = *(*world)->sac();
  Simulator sim((*world)->wall(), c->tools, (*world)->entry());
  constexpr std::size_t kMicroTool = 0, kFirst = 1, kSecond = 2;
  constexpr double kTip = 14.0;  // the microcatheter's tip ~1.8 mm past the neck
  drive(sim, kMicroTool, kTip, 0.01);
  ASSERT_GT(sac.depth_mm(sim.tip(kMicroTool).position_mm), 0.5);
  drive(sim, kFirst, kTip - 4.0, 0.01);
  drive(sim, kSecond, kTip - 9.0, 0.01);
  CoilMetrics metrics(sim, sac);
  drive(sim, kFirst, kTip + 61.5, 0.008, &metrics);  // 8 mm/s until the detachment zone is out
  ASSERT_EQ(release_coil(sim, kFirst, &metrics), DeviceError::kNone);
  drive(sim, kFirst, 0.0, 0.04, &metrics);
  drive(sim, kSecond, kTip - 4.0, 0.01, &metrics);
  const WorstOverlap overlap = push_watching_overlap(sim, kSecond, kTip + 41.5, 0.008, metrics);
  ASSERT_EQ(release_coil(sim, kSecond, &metrics), DeviceError::kNone);
  drive(sim, kSecond, 0.0, 0.04, &metrics);
  ASSERT_EQ(sim.detached_count(), 2u);
  expect_in_the_sac(sim, sac, (*world)->wall());
  EXPECT_EQ(metrics.figures().herniations, 0);
  EXPECT_LT(metrics.figures().kick_back_mm, 2.0);
  std::printf("two coils, microcatheter parked: kick-back %.2f mm, detach force %+.1f, %+.1f mN\n", metrics.figures().kick_back_mm,
              metrics.figures().detach_force_mN[0], metrics.figures().detach_force_mN[1]);
  EXPECT_NEAR(metrics.figures().deployed_mm, 100.0, 0.6);
  EXPECT_NEAR(metrics.figures().packing_density, 0.25 * std::acos(-1.0) * kCoilOd * kCoilOd * 100.0 / sac.volume_mm3, 1e-3);
  expect_packed_apart(sim, overlap);
}

// cases/neuro_coiling_dense.*: three coils (180 mm) through one microcatheter into the small round sac
// of neuro_small_aneurysm.hclm, each loaded only after the last was detached, each pushed out
// until its detachment zone is 0.1 mm past the tip (the script's markers, the microcatheter
// pushed to 152.5 mm: 152.6 mm + the coil's length), framing first (its loops 3.5 mm in the
// 3.94 mm dome), then loops of non-increasing size.
TEST(Coiling, DenseSequenceDetachesEachCoilBeforeTheNextAndPushesEachToItsMarkers) {
  const std::string dir = std::string(CATHBOX_SOURCE_DIR) + "/cases/";
  CaseParse c = load_case(dir + "neuro_coiling_dense.case");
  ASSERT_TRUE(c) << c.error().message;
  ScriptParse script = load_script(dir + "neuro_coiling_dense.actions");
  ASSERT_TRUE(script) << script.error().message;
  const auto coil = std::find_if(c->tools.begin(), c->tools.end(), [](const ToolSpec& t) { return t.kind == ToolKind::kCoil; });
  ASSERT_NE(coil, c->tools.end());
  std::vector<const ToolSection*> coils{&coil->sections.back()};
  for (const ToolSection& s : coil->next_coils) coils.push_back(&s);
  ASSERT_EQ(coils.size(), 3u);
  EXPECT_EQ(coils.front()->loop_diameter_mm, 3.5);
  double total = 0.0;
  for (std::size_t k = 0; k < coils.size(); ++k) {
    total += coils[k]->length_mm;
    if (k > 0) {
      EXPECT_LE(coils[k]->loop_diameter_mm, coils[k - 1]->loop_diameter_mm) << "coil " << k + 1;
    }
  }
  EXPECT_NEAR(total, 180.0, 1e-9);
  std::size_t loaded = 0, detached = 0;
  bool attached = true;
  for (const Action& a : script->actions) {
    if (a.kind == ActionKind::kDetach) {
      EXPECT_TRUE(attached) << "line " << a.line << ": detach with no coil attached";
      attached = false, ++detached;
    } else if (a.kind == ActionKind::kLoadCoil) {
      EXPECT_FALSE(attached) << "line " << a.line << ": load_coil before the last coil was detached";
      attached = true, ++loaded;
    } else if (a.kind == ActionKind::kInsertTo && a.speed == 8.0 && loaded < coils.size()) {
      EXPECT_NEAR(a.value, 152.6 + coils[loaded]->length_mm, 1e-9) << "line " << a.line;
    }
  }
  EXPECT_EQ(loaded, 2u);
  EXPECT_EQ(detached, 3u);
}

}  // namespace
}  // namespace cathbox::tool
