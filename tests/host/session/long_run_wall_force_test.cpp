// The browser test's long run (tests/browser/browser_test.py measure_long: y_bifurcation, the
// guidewire pushed to 90 mm, turned, pulled back to 30 mm, every 10 s) once read a peak wall force
// of exactly 1,800 mN over 30 minutes. 1,800 mN is the contact cap of the 0.36 mm wire: the wall
// penalty (2·10^5 mN/mm, tool::RodSettings::contact_stiffness_mN_per_mm) times the penetration
// limit (5 % of the 0.18 mm radius, 0.009 mm) that tool::Rod::limit_penetration holds a node to:
// a node the step left past the limit, clamped there, read as a force. Two changes since removed
// it: the session reads wall forces from converged steps only (session/contact_readings.hpp), and
// the rod's Newton loop holds a node it carried into the wall instead of clamping it at the cap
// (sim/tool rod_newton.cpp). Today the whole 30 minutes (CATHBOX_LONG_RUN_SECONDS=1800, ~64 s
// CPU) has no contact at the cap, converged or not, and a peak wall force of 57.0 mN, the same
// record size as the browser test's (325,047 bytes); by default the test runs its first 120 s.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "session/action_script_hand.hpp"
#include "session/session.hpp"
#include "tool/rod_settings.hpp"

namespace cathbox::session {
namespace {

// Ticks at which any contact of any tool reads its cap (≥ 0.999 of it), converged or not.
class CapWatch : public TickObserver {
 public:
  void observe(const TickView& v) override {
    ++tick;
    const tool::RodSettings settings;  // the simulator's defaults
    for (std::size_t u = 0; u < v.sim.tool_count(); ++u) {
      const tool::Rod& rod = v.sim.rod(u);
      for (const tool::RodContact& k : rod.contacts()) {
        const double cap = settings.contact_stiffness_mN_per_mm * settings.max_penetration_ratio * rod.node_radius_mm(k.node);
        if (k.normal_force_mN < 0.999 * cap) continue;
        cap_mN = cap;
        raw_peak_mN = std::max(raw_peak_mN, k.normal_force_mN);
        if (rod.converged()) ++capped_converged;
        else ++capped_unconverged;
        if (first_capped_tick < 0) first_capped_tick = tick;
      }
    }
  }
  std::int64_t tick = 0;
  std::int64_t first_capped_tick = -1;
  std::int64_t capped_converged = 0;
  std::int64_t capped_unconverged = 0;
  double cap_mN = 0.0;
  double raw_peak_mN = 0.0;
};

// The browser test's script (measure_long), for `seconds`.
std::string write_long_script(int seconds) {
  const std::string path = testing::TempDir() + "long_run_wall_force.actions";
  std::ofstream f(path);
  f << "0 select guidewire\n";
  for (int t = 0; t < seconds * 1000; t += 10'000) {
    f << t << " insert_to 90 at 20\n" << t + 4000 << " rotate_to " << (t / 1000) % 720 << " at 90\n" << t + 6000 << " insert_to 30 at 20\n";
  }
  f << seconds * 1000 << " end\n";
  return path;
}

TEST(LongRunWallForce, NoContactReachesTheWiresCapOf1800mN) {
  const char* env = std::getenv("CATHBOX_LONG_RUN_SECONDS");
  const int seconds = env != nullptr ? std::atoi(env) : 120;
  const std::string dir = std::string(CATHBOX_SOURCE_DIR) + "/cases/";
  SessionCaseLoad loaded = load_session_case(dir + "y_bifurcation.case");
  ASSERT_TRUE(loaded) << loaded.error().message;
  auto script = ActionScriptHand::load(write_long_script(seconds), *loaded.value());
  ASSERT_TRUE(script) << (script ? "" : script.error().message);
  auto hand = std::move(*script);
  Session s(std::move(loaded.value()), std::move(hand));
  CapWatch watch;
  s.add_observer(watch);
  s.step_virtual(std::int64_t{seconds} * 1000);
  std::printf("first capped tick %lld, capped contacts: %lld unconverged, %lld converged; cap %.1f mN, raw peak %.1f mN; peak wall "
              "force %.1f mN\n",
              static_cast<long long>(watch.first_capped_tick), static_cast<long long>(watch.capped_unconverged),
              static_cast<long long>(watch.capped_converged), watch.cap_mN, watch.raw_peak_mN, s.metrics().peak_wall_force_mN);
  const tool::RodSettings settings;
  const double wire_cap_mN = settings.contact_stiffness_mN_per_mm * settings.max_penetration_ratio * s.simulator().rod(0).node_radius_mm(0);
  EXPECT_DOUBLE_EQ(wire_cap_mN, 1800.0) << "the figure the long run once read";
  EXPECT_EQ(watch.capped_unconverged, 0) << "first at tick " << watch.first_capped_tick;
  EXPECT_EQ(watch.capped_converged, 0) << "first at tick " << watch.first_capped_tick;
  EXPECT_LT(s.metrics().peak_wall_force_mN, 0.1 * wire_cap_mN);
  EXPECT_GT(s.metrics().wall_contacts, 0) << "the wire touches the wall";
}

}  // namespace
}  // namespace cathbox::session
