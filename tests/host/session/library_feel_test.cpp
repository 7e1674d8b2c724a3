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

namespace cathbox::session {
namespace {

using test::kFullScale_mN;
using test::kSlewPerTick_mN;

// Every tool's hand force, tick by tick.
class EveryToolForce : public TickObserver {
 public:
  struct Tool {
    double peak_mN = 0.0, last_mN = 0.0, largest_change_mN = 0.0;
    std::int64_t peak_ms = 0, change_ms = 0, over_slew = 0;
    // The largest excess of the clamp's own force over the free part's loads, and when.
    double over_free_body_mN = 0.0;
    std::int64_t over_free_body_ms = 0;
  };
  void observe(const TickView& v) override {
    const tool::Simulator& sim = v.sim;
    // (A tool's force is its own from tick to tick, held by the hand or not: with a box per tool
    // each box renders its tool's.)
    tools.resize(sim.tool_count());
    names.resize(sim.tool_count());
    for (std::size_t t = 0; t < sim.tool_count(); ++t) {
      Tool& k = tools[t];
      names[t] = sim.rod(t).spec().name;
      const double f = sim.hand_force_mN(t);
      const std::int64_t ms = v.time_us / 1000;
      if (std::abs(f) > k.peak_mN) k.peak_mN = std::abs(f), k.peak_ms = ms;
      if (ticks_ > 0) {
        const double change = std::abs(f - k.last_mN);
        if (change > k.largest_change_mN) k.largest_change_mN = change, k.change_ms = ms;
        if (change > kSlewPerTick_mN) ++k.over_slew;
      }
      k.last_mN = f;
      const tool::Rod& rod = sim.rod(t);
      const double excess = std::abs(rod.hand_force_mN()) - rod.free_part_load_mN();
      if (excess > k.over_free_body_mN) k.over_free_body_mN = excess, k.over_free_body_ms = ms;
    }
    ++ticks_;
  }
  std::vector<Tool> tools;
  std::vector<std::string> names;

 private:
  std::int64_t ticks_ = 0;
};

struct ScriptedRun {
  EveryToolForce force;
  Metrics metrics;
};

// Runs a case with an action script in virtual time to its end (the script's, or the target).
void run_scripted(const std::string& case_file, const std::string& actions, ScriptedRun& run) {
  ASSERT_TRUE(test::run_scripted(case_file, actions, run.force, run.metrics));
  for (std::size_t t = 0; t < run.force.tools.size(); ++t) {
    const EveryToolForce::Tool& k = run.force.tools[t];
    std::printf("  %-14s peak %7.1f mN at %6.3f s; largest change %7.1f mN/tick at %6.3f s, %lld ticks over %.0f\n",
                run.force.names[t].c_str(), k.peak_mN, 1e-3 * static_cast<double>(k.peak_ms), k.largest_change_mN,
                1e-3 * static_cast<double>(k.change_ms), static_cast<long long>(k.over_slew), kSlewPerTick_mN);
  }
}

// The library cases whose scripted run still changes a tool's force by more than the box's slew
// (docs/sim-tool/convergence.md, "The case library's runs at the hand"): the bovine arch's wire
// leaving the catheter's tip (4 ticks), the MCA run's wire leaving the microcatheter's tip pressed
// on the wall at its junction (44 ticks, node crossings).
const std::vector<std::string> kSlewNotYet{"aneurysm_mca", "arch_bovine"};

// Every bundled library case (cases/library/NAME.case), or those whose slew is met or not.
enum class Slew { kAny, kMet, kNotYet };
std::vector<std::string> library_cases(Slew slew) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(std::string(CATHBOX_SOURCE_DIR) + "/cases/library")) {
    if (e.path().extension() != ".case") continue;
    const std::string name = e.path().stem().string();
    const bool not_yet = std::find(kSlewNotYet.begin(), kSlewNotYet.end(), name) != kSlewNotYet.end();
    if (slew == Slew::kAny || not_yet == (slew == Slew::kNotYet)) names.push_back(name);
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
  ASSERT_FALSE(run.force.tools.empty());
  EXPECT_TRUE(run.metrics.target_reached) << "closest " << run.metrics.closest_to_target_mm << " mm";
  for (std::size_t t = 0; t < run.force.tools.size(); ++t) {
    EXPECT_LE(run.force.tools[t].peak_mN, kFullScale_mN) << run.force.names[t] << " at " << run.force.tools[t].peak_ms << " ms";
  }
}

// Every tool within the full scale and its force changing by no more than the slew a tick.
class LibraryFeel : public ::testing::TestWithParam<std::string> {};

TEST_P(LibraryFeel, EveryToolsForceStaysWithinTheBoxsFullScaleAndSlewOnTheWayToTheTarget) {
  const ScriptedRun run = run_library_case(GetParam());
  expect_reached_within_full_scale(run);
  for (std::size_t t = 0; t < run.force.tools.size(); ++t) {
    EXPECT_EQ(run.force.tools[t].over_slew, 0)
        << run.force.names[t] << ": " << run.force.tools[t].largest_change_mN << " mN at " << run.force.tools[t].change_ms << " ms";
  }
}

INSTANTIATE_TEST_SUITE_P(Meets, LibraryFeel, ::testing::ValuesIn(library_cases(Slew::kMet)), param_name);
INSTANTIATE_TEST_SUITE_P(DISABLED_NotYet, LibraryFeel, ::testing::ValuesIn(library_cases(Slew::kNotYet)), param_name);

// The cases not meeting the slew yet still hold the full scale.
class LibraryFullScale : public ::testing::TestWithParam<std::string> {};

TEST_P(LibraryFullScale, EveryToolsForceStaysWithinTheBoxsFullScaleOnTheWayToTheTarget) {
  expect_reached_within_full_scale(run_library_case(GetParam()));
}

INSTANTIATE_TEST_SUITE_P(SlewNotYet, LibraryFullScale, ::testing::ValuesIn(library_cases(Slew::kNotYet)), param_name);

TEST(LibraryCases, EveryCaseIsRunByTheFeelTests) {
  EXPECT_EQ(library_cases(Slew::kMet).size() + library_cases(Slew::kNotYet).size(), library_cases(Slew::kAny).size());
  EXPECT_GE(library_cases(Slew::kAny).size(), 12U);
  for (const std::string& name : kSlewNotYet) {
    const auto all = library_cases(Slew::kAny);
    EXPECT_NE(std::find(all.begin(), all.end(), name), all.end()) << name << " is not a library case";
  }
}

// The basilar case with its microwire pushed on at 10 mm/s while the microcatheter advances over
// it (a careless hand): the wire jams 15 mm out of the microcatheter's tip. Its clamp, linearised
// on to the moves after the solve, read 12.8-13.7 N there against 2.2 N of external forces on its
// free part; now no tool's own force is above its free part's loads, and the wire's hand force
// stays under the box's full scale.
TEST(LibraryFeelJammed, AToolsOwnForceIsNoMoreThanItsFreePartsLoads) {
  ScriptedRun run;
  run_scripted(std::string(CATHBOX_SOURCE_DIR) + "/cases/library/aneurysm_basilar.case",
               std::string(CATHBOX_SOURCE_DIR) + "/tests/host/session/data/basilar_wire_jammed.actions", run);
  ASSERT_EQ(run.force.tools.size(), 3U);
  const EveryToolForce::Tool& wire = run.force.tools[2];
  EXPECT_GT(wire.peak_mN, 2000.0) << "the wire does not jam: the script no longer tests the bound";
  for (std::size_t t = 0; t < run.force.tools.size(); ++t) {
    EXPECT_LE(run.force.tools[t].over_free_body_mN, 1e-6)
        << run.force.names[t] << " at " << run.force.tools[t].over_free_body_ms << " ms";
    EXPECT_LE(run.force.tools[t].peak_mN, kFullScale_mN) << run.force.names[t];
  }
}

}  // namespace
}  // namespace cathbox::session
