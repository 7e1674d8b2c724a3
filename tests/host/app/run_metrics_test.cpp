#include "app/run_metrics.hpp"

#include <gtest/gtest.h>

namespace cathbox::app {
namespace {

TEST(RunMetrics, AccumulatesPathTimeAndPeaks) {
  RunMetrics m;
  for (int i = 0; i <= 1000; ++i) {
    TickObservation t;
    t.time_us = 2'000'000 + i * 1000;
    t.tip_mm = glm::vec3(0.05F * static_cast<float>(i), 0.0F, 0.0F);  // 50 mm/s
    t.hand_force_mN = i == 500 ? 120.0 : 10.0;
    t.wall_force_mN = i == 700 ? 80.0 : 0.0;
    m.observe(t);
  }
  const RunSummary& s = m.summary();
  EXPECT_EQ(s.elapsed_us, 1'000'000);
  EXPECT_NEAR(s.path_length_mm, 50.0, 1e-3);
  EXPECT_DOUBLE_EQ(s.peak_hand_force_mN, 120.0);
  EXPECT_DOUBLE_EQ(s.peak_wall_force_mN, 80.0);
  EXPECT_FALSE(m.has_target());
  EXPECT_NE(RunMetrics::format(s).find("none in this case"), std::string::npos);
}

TEST(RunMetrics, CountsContactEpisodesNotTicks) {
  RunMetrics m(std::nullopt, 2.0, 20'000);
  auto feed = [&](std::int64_t from_ms, std::int64_t to_ms, bool contact) {
    for (std::int64_t ms = from_ms; ms < to_ms; ++ms) {
      TickObservation t;
      t.time_us = ms * 1000;
      t.tip_in_contact = contact;
      m.observe(t);
    }
  };
  feed(0, 10, false);
  feed(10, 50, true);    // episode 1
  feed(50, 55, false);   // 5 ms gap: chatter, same episode
  feed(55, 80, true);
  feed(80, 200, false);  // long gap
  feed(200, 210, true);  // episode 2
  EXPECT_EQ(m.summary().wall_contacts, 2);
}

TEST(RunMetrics, DetectsTheTargetOnceAndKeepsTheClosestApproach) {
  RunMetrics m(glm::vec3(10.0F, 0.0F, 0.0F), 1.5);
  for (int i = 0; i <= 20; ++i) {
    TickObservation t;
    t.time_us = i * 1000;
    t.tip_mm = glm::vec3(static_cast<float>(i), 0.0F, 0.0F);
    m.observe(t);
  }
  const RunSummary& s = m.summary();
  EXPECT_TRUE(s.reached_target);
  EXPECT_EQ(s.reached_at_us, 9000);  // 1 mm away at 9 ms
  EXPECT_NEAR(s.closest_to_target_mm, 0.0, 1e-9);
  EXPECT_NE(RunMetrics::format(s).find("reached at 0.01 s"), std::string::npos);
}

TEST(RunMetrics, ReportsAMissWithTheClosestDistance) {
  RunMetrics m(glm::vec3(0.0F, 10.0F, 0.0F), 1.0);
  TickObservation t;
  t.tip_mm = glm::vec3(0.0F, 4.0F, 0.0F);
  m.observe(t);
  EXPECT_FALSE(m.summary().reached_target);
  EXPECT_NE(RunMetrics::format(m.summary()).find("closest 6.0 mm"), std::string::npos);
}

}  // namespace
}  // namespace cathbox::app
