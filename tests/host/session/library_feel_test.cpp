// The case library's scripted runs (cases/library, every NAME.case with its NAME.actions) as the
// hand would feel them with a box on every tool (`cathbox session run --box TOOL=WHERE` renders
// each tool's force on its own box): every tool's hand force within the box's 5 N full scale on
// every tick, its change between ticks within the box's slew (100 mN), and the target reached
// (issue 29, "the feel": each bundled case). Per tool the peak, the largest change between ticks
// and the ticks changing by more than the slew are printed. And the free-body bound on a jammed
// wire: a tool's own part of its hand force (its clamp) is no more than the external forces on its
// free part sum to.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "hand_force_trace.hpp"
#include "session/tool_forces.hpp"

namespace cathbox::session {
namespace {

using test::kFullScale_mN;
using test::kSlewPerTick_mN;

// Every tool's hand force, tick by tick (session::ToolForces, as `cathbox session replay --forces`
// prints it), and the largest excess of each tool's clamp force over its free part's loads.
class EveryToolForce : public TickObserver {
 public:
  void observe(const TickView& v) override {
    forces.observe(v);
    over_free_body_mN.resize(v.sim.tool_count(), 0.0);
    over_free_body_ms.resize(v.sim.tool_count(), 0);
    for (std::size_t t = 0; t < v.sim.tool_count(); ++t) {
      const tool::Rod& rod = v.sim.rod(t);
      const double excess = std::abs(rod.hand_force_mN()) - rod.free_part_load_mN();
      if (excess > over_free_body_mN[t]) over_free_body_mN[t] = excess, over_free_body_ms[t] = v.time_us / 1000;
    }
  }
  [[nodiscard]] const std::vector<ToolForces::Tool>& tools() const { return forces.tools(); }
  ToolForces forces;
  std::vector<double> over_free_body_mN;
  std::vector<std::int64_t> over_free_body_ms;
};

struct ScriptedRun {
  EveryToolForce force;
  Metrics metrics;
};

double seconds(std::int64_t us) { return 1e-6 * static_cast<double>(us); }

// Runs a case with an action script in virtual time to its end (the script's, or the target).
void run_scripted(const std::string& case_file, const std::string& actions, ScriptedRun& run) {
  ASSERT_TRUE(test::run_scripted(case_file, actions, run.force, run.metrics));
  EXPECT_EQ(run.force.forces.slew_per_tick_mN(), kSlewPerTick_mN);
  EXPECT_EQ(run.force.forces.full_scale_mN(), kFullScale_mN);
  std::printf("%s", run.force.forces.format().c_str());
}

// Every bundled library case (cases/library/NAME.case).
std::vector<std::string> library_cases() {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(std::string(CATHBOX_SOURCE_DIR) + "/cases/library")) {
    if (e.path().extension() == ".case") names.push_back(e.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::string param_name(const ::testing::TestParamInfo<std::string>& info) { return info.param; }

ScriptedRun run_library_case(const std::string& name) {
  const std::string dir = std::string(CATHBOX_SOURCE_DIR) + "/cases/library/";
  ScriptedRun run;
  run_scripted(dir + name + ".case", dir + name + ".actions", run);
  return run;
}

void expect_reached_within_full_scale(const ScriptedRun& run) {
  ASSERT_FALSE(run.force.tools().empty());
  EXPECT_TRUE(run.metrics.target_reached) << "closest " << run.metrics.closest_to_target_mm << " mm";
  for (const ToolForces::Tool& k : run.force.tools()) {
    EXPECT_LE(k.peak_mN, kFullScale_mN) << k.name << " at " << seconds(k.peak_us) << " s";
  }
}

// Every tool within the full scale and its force changing by no more than the slew a tick.
class LibraryFeel : public ::testing::TestWithParam<std::string> {};

TEST_P(LibraryFeel, EveryToolsForceStaysWithinTheBoxsFullScaleAndSlewOnTheWayToTheTarget) {
  const ScriptedRun run = run_library_case(GetParam());
  expect_reached_within_full_scale(run);
  for (const ToolForces::Tool& k : run.force.tools()) {
    EXPECT_EQ(k.over_slew, 0) << k.name << ": " << k.largest_change_mN << " mN at " << seconds(k.change_us) << " s";
  }
}

INSTANTIATE_TEST_SUITE_P(Meets, LibraryFeel, ::testing::ValuesIn(library_cases()), param_name);

TEST(LibraryCases, EveryCaseIsRunByTheFeelTests) { EXPECT_GE(library_cases().size(), 12U); }

// The basilar case with its microwire pushed on at 10 mm/s while the microcatheter advances over
// it (a careless hand): the wire jams 15 mm out of the microcatheter's tip. Its clamp, linearised
// on to the moves after the solve, read 12.8-13.7 N there against 2.2 N of external forces on its
// free part; now no tool's own force is above its free part's loads, and the wire's hand force
// stays under the box's full scale.
TEST(LibraryFeelJammed, AToolsOwnForceIsNoMoreThanItsFreePartsLoads) {
  ScriptedRun run;
  run_scripted(std::string(CATHBOX_SOURCE_DIR) + "/cases/library/aneurysm_basilar.case",
               std::string(CATHBOX_SOURCE_DIR) + "/tests/host/session/data/basilar_wire_jammed.actions", run);
  ASSERT_EQ(run.force.tools().size(), 3U);
  ASSERT_EQ(run.force.over_free_body_mN.size(), 3U);
  const ToolForces::Tool& wire = run.force.tools()[2];
  EXPECT_GT(wire.peak_mN, 2000.0) << "the wire does not jam: the script no longer tests the bound";
  for (std::size_t t = 0; t < run.force.tools().size(); ++t) {
    const ToolForces::Tool& k = run.force.tools()[t];
    EXPECT_LE(run.force.over_free_body_mN[t], 1e-6) << k.name << " at " << run.force.over_free_body_ms[t] << " ms";
    EXPECT_LE(k.peak_mN, kFullScale_mN) << k.name;
  }
}

}  // namespace
}  // namespace cathbox::session
