// Every metric on a trace whose answer is worked out by hand (host/session/README.md,
// "Metrics", has the definitions).
#include "session/metrics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace cathbox::session {
namespace {

// Feeds ticks of 1 ms from `from_ms` to `to_ms` (excluded), each filled in by `fill`.
void feed(MetricsCollector& m, std::int64_t from_ms, std::int64_t to_ms, const std::function<void(MetricsTick&, std::int64_t)>& fill) {
  for (std::int64_t ms = from_ms; ms < to_ms; ++ms) {
    MetricsTick t;
    t.time_us = ms * 1000;
    fill(t, ms);
    m.observe(t);
  }
}

TEST(Metrics, ProcedureTimePathAndPeaks) {
  MetricsCollector m;
  feed(m, 2000, 3001, [](MetricsTick& t, std::int64_t ms) {
    const auto i = static_cast<float>(ms - 2000);
    t.tip_mm = glm::vec3(0.05F * i, 0.0F, 0.0F);  // 50 mm/s along x
    t.hand_force_mN = ms == 2500 ? 120.0 : 10.0;
    t.wall_force_mN = ms == 2700 ? 80.0 : 0.0;
  });
  const Metrics& s = m.metrics();
  EXPECT_EQ(s.procedure_time_us, 1'000'000);      // 2.000 s to 3.000 s
  EXPECT_NEAR(s.tip_path_mm, 50.0, 1e-3);          // 1000 steps of 0.05 mm
  EXPECT_DOUBLE_EQ(s.peak_hand_force_mN, 120.0);
  EXPECT_DOUBLE_EQ(s.peak_wall_force_mN, 80.0);
  EXPECT_FALSE(s.has_target);
  EXPECT_EQ(s.wrong_branch_entries, -1);  // no route without a target
  EXPECT_LT(s.path_efficiency, 0.0);
  EXPECT_NE(MetricsCollector::format(s).find("none in this case"), std::string::npos);
  EXPECT_NE(MetricsCollector::format(s).find("fluoroscopy time      n/a"), std::string::npos);
}

TEST(Metrics, CountsContactEpisodesNotTicks) {
  MetricsSettings settings;
  settings.contact_gap_us = 20'000;
  MetricsCollector m(settings);
  auto contact = [&](std::int64_t from, std::int64_t to, bool on) {
    feed(m, from, to, [on](MetricsTick& t, std::int64_t) { t.tip_in_contact = on; });
  };
  contact(0, 10, false);
  contact(10, 50, true);    // episode 1
  contact(50, 55, false);   // 5 ms gap: chatter, the same episode
  contact(55, 80, true);
  contact(80, 200, false);  // 120 ms gap
  contact(200, 210, true);  // episode 2
  EXPECT_EQ(m.metrics().wall_contacts, 2);
}

TEST(Metrics, TimeAboveTheWallForceThreshold) {
  MetricsSettings settings;
  settings.wall_force_threshold_mN = 100.0;
  MetricsCollector m(settings);
  // 0-99 ms: 50 mN; 100-129 ms: 150 mN (30 ticks above); 130-199 ms: 100 mN (not above);
  // 200-204 ms: 101 mN (5 ticks above). Each tick above counts the 1 ms since the last.
  feed(m, 0, 205, [](MetricsTick& t, std::int64_t ms) {
    t.wall_force_mN = ms < 100 ? 50.0 : ms < 130 ? 150.0 : ms < 200 ? 100.0 : 101.0;
  });
  EXPECT_EQ(m.metrics().time_above_threshold_us, 35'000);
  EXPECT_DOUBLE_EQ(m.metrics().wall_force_threshold_mN, 100.0);
}

TEST(Metrics, TargetTimeClosestApproachAndPathEfficiency) {
  MetricsSettings settings;
  settings.target_mm = glm::vec3(10.0F, 0.0F, 0.0F);
  settings.target_radius_mm = 1.5;
  settings.route_length_mm = 10.0;
  MetricsCollector m(settings);
  // The tip goes 0 -> 3 mm, back to 1 mm, then on to 20 mm in 1 mm steps: when it first comes
  // within 1.5 mm of x = 10 (at x = 9) it has travelled 3 + 2 + 8 = 13 mm.
  const std::vector<float> xs = {0, 1, 2, 3, 2, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
  std::int64_t ms = 0;
  for (const float x : xs) {
    MetricsTick t;
    t.time_us = ms++ * 1000;
    t.tip_mm = glm::vec3(x, 0.0F, 0.0F);
    m.observe(t);
  }
  const Metrics& s = m.metrics();
  EXPECT_TRUE(s.target_reached);
  EXPECT_EQ(s.time_to_target_us, 13'000);  // x = 9 is the 14th sample
  EXPECT_NEAR(s.closest_to_target_mm, 0.0, 1e-9);
  EXPECT_NEAR(s.path_efficiency, 10.0 / 13.0, 1e-9);
  EXPECT_NEAR(s.tip_path_mm, 15.0, 1e-6);  // the path goes on after the target
  EXPECT_NE(MetricsCollector::format(s).find("reached at 0.01 s"), std::string::npos);
}

TEST(Metrics, AMissReportsTheClosestDistance) {
  MetricsSettings settings;
  settings.target_mm = glm::vec3(0.0F, 10.0F, 0.0F);
  settings.target_radius_mm = 1.0;
  MetricsCollector m(settings);
  MetricsTick t;
  t.tip_mm = glm::vec3(0.0F, 4.0F, 0.0F);
  m.observe(t);
  EXPECT_FALSE(m.metrics().target_reached);
  EXPECT_EQ(m.metrics().time_to_target_us, -1);
  EXPECT_NE(MetricsCollector::format(m.metrics()).find("closest 6.0 mm"), std::string::npos);
}

TEST(Metrics, WrongBranchEntriesCountEachEntryOnce) {
  MetricsSettings settings;
  settings.target_mm = glm::vec3(100.0F);
  settings.route_segments = {0, 1, 4};
  MetricsCollector m(settings);
  // Segments the tip is in, tick by tick: -2 is a junction, -1 none.
  // 0 0 -2 1 1 -2 2 2 -2 2 -2 1 -2 3 3 -1 3 1 4  -> entries into 2 (once, the junction in
  // between does not end it), into 3 (once, "none" does not end it): 2.
  const std::vector<std::int32_t> segs = {0, 0, -2, 1, 1, -2, 2, 2, -2, 2, -2, 1, -2, 3, 3, -1, 3, 1, 4};
  std::int64_t ms = 0;
  for (const std::int32_t seg : segs) {
    MetricsTick t;
    t.time_us = ms++ * 1000;
    t.tip_segment = seg;
    m.observe(t);
  }
  EXPECT_EQ(m.metrics().wrong_branch_entries, 2);
  // Back into 2 again later: a third entry.
  MetricsTick t;
  t.time_us = ms * 1000;
  t.tip_segment = 2;
  m.observe(t);
  EXPECT_EQ(m.metrics().wrong_branch_entries, 3);
}

TEST(Metrics, RetractionsNeedTwoMillimetresEachWay) {
  MetricsCollector m;  // retraction_mm = 2
  // Insertion (mm) tick by tick: up to 10, back to 7 (3 mm: retraction 1), up to 12, back to
  // 11 (1 mm: none), to 9.5 (2.5 mm below 12: retraction 2), 10 (not 2 mm above 9.5: still
  // retracting), 8 (lowest), 10.5 (2.5 above 8: advancing again), 8.4 (2.1 mm: retraction 3).
  const std::vector<double> xs = {0, 5, 10, 9, 7, 9, 12, 11, 9.5, 10, 8, 10.5, 8.4};
  std::int64_t ms = 0;
  for (const double x : xs) {
    MetricsTick t;
    t.time_us = ms++ * 1000;
    t.held_insertion_mm = x;
    m.observe(t);
  }
  EXPECT_EQ(m.metrics().retractions, 3);
}

TEST(Metrics, PeakInsertionSpeedOverFiftyMilliseconds) {
  MetricsCollector m;  // 50 ms window
  // 20 mm/s for 200 ms, then a 1 ms jerk of 0.5 mm, then still: over any 50 ms window the
  // largest change is 0.02 * 49 + 0.5 = 1.48 mm (the window ending at the jerk): 29.6 mm/s.
  double x = 0.0;
  feed(m, 0, 400, [&x](MetricsTick& t, std::int64_t ms) {
    if (ms > 0 && ms <= 200) x += 0.02;
    if (ms == 201) x += 0.5;
    t.held_insertion_mm = x;
  });
  EXPECT_NEAR(m.metrics().peak_insertion_speed_mm_s, 1.48 / 0.05, 1e-6);
}

TEST(Metrics, ToolChangesAndNoTravelWhenTakingAnotherTool) {
  MetricsCollector m;
  MetricsTick t;
  t.tip_mm = glm::vec3(0.0F);
  m.observe(t);
  t.time_us = 1000;
  t.tip_mm = glm::vec3(1.0F, 0.0F, 0.0F);
  m.observe(t);
  // The other tool's tip is 30 mm away: not travel.
  t.time_us = 2000;
  t.held = 1;
  t.tool_changed = true;
  t.tip_mm = glm::vec3(31.0F, 0.0F, 0.0F);
  m.observe(t);
  t.time_us = 3000;
  t.tool_changed = false;
  t.tip_mm = glm::vec3(33.0F, 0.0F, 0.0F);
  m.observe(t);
  EXPECT_EQ(m.metrics().tool_changes, 1);
  EXPECT_NEAR(m.metrics().tip_path_mm, 3.0, 1e-6);
}

TEST(Metrics, FluoroscopyFiguresStayEmptyUntilTheirModuleFillsThem) {
  const Metrics m;
  EXPECT_FALSE(m.fluoroscopy_time_s);
  EXPECT_FALSE(m.dose_area_product_mGy_cm2);
  EXPECT_FALSE(m.fluoroscopy_runs);
  EXPECT_FALSE(m.contrast_volume_ml);
}

// Every named metric of `s` is one metric_names() lists, and each of `want` is named once with its value.
void expect_named(const Metrics& s, const std::vector<std::pair<std::string, double>>& want) {
  const std::vector<std::string> names = metric_names();
  for (const NamedMetric& n : named_metrics(s)) EXPECT_NE(std::find(names.begin(), names.end(), n.name), names.end()) << n.name;
  for (const auto& [name, value] : want) {
    int found = 0;
    for (const NamedMetric& n : named_metrics(s)) found += n.name == name ? (n.value == value ? 1 : 100) : 0;
    EXPECT_EQ(found, 1) << name;
  }
}

// The coiling figures as tool::CoilMetrics gives them: packing as a percentage, the herniation
// count and its extent and the microcatheter's kick-forward named for the server (every name one metric_names() lists) and printed,
// the extent only once a coil has herniated.
TEST(Metrics, CoilingFiguresCarryTheHerniationsExtent) {
  MetricsCollector m;
  tool::CoilFigures f;
  f.packing_density = 0.25;
  f.deployed_mm = 310.0;
  m.set_coiling(f);
  EXPECT_EQ(MetricsCollector::format(m.metrics()).find("herniation extent"), std::string::npos) << "none herniated";
  f.herniations = 1;
  f.herniated_nodes = 3;
  f.herniated_peak_nodes = 51;
  f.herniated_depth_mm = 2.33;
  f.kick_back_mm = 0.16;
  f.kick_forward_mm = 2.2;
  m.set_coiling(f);
  const Metrics& s = m.metrics();
  EXPECT_DOUBLE_EQ(*s.packing_density_pct, 25.0);
  EXPECT_EQ(*s.coil_herniations, 1);
  EXPECT_EQ(*s.coil_herniated_peak_nodes, 51);
  EXPECT_DOUBLE_EQ(*s.coil_herniated_depth_mm, 2.33);
  expect_named(s, {{"coil_herniated_peak_nodes", 51.0}, {"coil_herniated_depth_mm", 2.33}, {"kick_forward_mm", 2.2}});
  EXPECT_NE(MetricsCollector::format(s).find("herniation extent     up to 51 nodes at once, 2.33 mm past the neck plane"),
            std::string::npos)
      << MetricsCollector::format(s);
}

// Each detachment's pusher force as tool::CoilMetrics gives it: kept in order, the largest and the
// count under tension named for the server (metric_names() lists them), printed once a coil is off.
TEST(Metrics, CoilingFiguresCarryTheDetachForces) {
  MetricsCollector m;
  tool::CoilFigures f;
  f.packing_density = 0.02;
  m.set_coiling(f);
  EXPECT_TRUE(m.metrics().coil_detach_force_mN.empty());
  EXPECT_EQ(MetricsCollector::format(m.metrics()).find("detach force"), std::string::npos) << "none detached";
  f.detachments = 2;
  f.detach_force_mN[0] = 288.5;
  f.detach_force_mN[1] = -4.25;
  f.detach_force_peak_mN = 288.5;
  f.detached_under_tension = 1;
  m.set_coiling(f);
  const Metrics& s = m.metrics();
  EXPECT_EQ(s.coil_detach_force_mN, (std::vector<double>{288.5, -4.25}));
  expect_named(s, {{"coil_detach_force_peak_mN", 288.5}, {"coil_detached_under_tension", 1.0}});
  EXPECT_NE(MetricsCollector::format(s).find("detach force          +288.5, -4.2 mN (1 under tension, over 30 mN)"), std::string::npos)
      << MetricsCollector::format(s);
}

}  // namespace
}  // namespace cathbox::session
