#include "session/haptic_thread.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "session/haptic_pacer.hpp"
#include "session/rate_meter.hpp"

namespace cathbox::session {
namespace {

TEST(HapticPacer, OneTickPerPeriodWhenOnTime) {
  HapticPacer p(1000, 0);
  EXPECT_EQ(p.due(0).ticks, 1);
  EXPECT_EQ(p.due(500).ticks, 0);
  EXPECT_EQ(p.next_deadline_us(), 1000);
  EXPECT_EQ(p.due(1000).ticks, 1);
  EXPECT_EQ(p.due(1999).ticks, 0);
}

TEST(HapticPacer, CatchesUpASmallDelayAndDropsAStall) {
  HapticPacer p(1000, 0, 4);
  ASSERT_EQ(p.due(0).ticks, 1);
  // 2.5 ms late: the 1, 2 and 3 ms ticks are due.
  EXPECT_EQ(p.due(3500).ticks, 3);
  EXPECT_EQ(p.next_deadline_us(), 4000);
  // A 50 ms stall: at most 4 run, the rest are dropped and counted.
  const HapticPacer::Due d = p.due(54000);
  EXPECT_EQ(d.ticks, 4);
  EXPECT_EQ(d.dropped, 47);
  EXPECT_EQ(p.dropped_total(), 47);
  EXPECT_EQ(p.next_deadline_us(), 55000);
}

TEST(RateMeter, MeasuresEventsPerSecondOfTheGivenTime) {
  RateMeter m(100'000);
  for (std::int64_t t = 0; t <= 300'000; t += 1000) m.tick(t);
  EXPECT_NEAR(m.rate_hz(), 1000.0, 1e-9);
  for (std::int64_t t = 301'000; t <= 700'000; t += 2000) m.tick(t);
  EXPECT_NEAR(m.rate_hz(), 500.0, 1.0);
}

TEST(HapticThread, RunsOneTickPerMillisecondOfVirtualTime) {
  VirtualClock clock(5'000'000);
  std::vector<std::int64_t> sim_times;
  HapticThread loop(clock, 1000, [&](std::int64_t t) {
    sim_times.push_back(t);
    return true;
  });
  loop.run(std::stop_token{}, 3000);
  ASSERT_EQ(sim_times.size(), 3000U);
  for (std::size_t i = 0; i < sim_times.size(); ++i) {
    ASSERT_EQ(sim_times[i], static_cast<std::int64_t>(i) * 1000);
  }
  EXPECT_EQ(clock.now_us(), 5'000'000 + 2'999'000);
  EXPECT_EQ(loop.dropped(), 0);
  EXPECT_NEAR(loop.rate_hz(), 1000.0, 1.0);
}

TEST(HapticThread, TheTickFunctionEndsTheRun) {
  VirtualClock clock;
  int n = 0;
  HapticThread loop(clock, 1000, [&](std::int64_t) { return ++n < 10; });
  loop.run(std::stop_token{});
  EXPECT_EQ(n, 10);
  EXPECT_TRUE(loop.finished());
}

TEST(HapticThread, AStallInsideATickIsCountedAsDroppedTicks) {
  VirtualClock clock;
  HapticThread loop(clock, 1000, [&](std::int64_t t) {
    if (t == 100'000) clock.advance_us(30'000);  // this tick takes 30 ms
    return true;
  });
  loop.run(std::stop_token{}, 500);
  EXPECT_EQ(loop.ticks(), 500);
  EXPECT_EQ(loop.dropped(), 26);  // 30 late ticks, 4 caught up
}

// The idle work runs once in each wait after the ticks that were due, before the next tick,
// and not while the loop is catching up (a tick that overran goes straight on to the next) nor
// with less than half a period left (a tick that ran long). A run ended by its tick count does it
// before it returns.
TEST(HapticThread, RunsTheIdleWorkOnceInEachWaitAndNeverWhileLate) {
  VirtualClock clock;
  std::vector<std::int64_t> events;  // a tick's time, or -1 for the idle work
  HapticThread loop(
      clock, 1000,
      [&](std::int64_t t) {
        events.push_back(t);
        if (t == 5000) clock.advance_us(2500);  // this tick takes 2.5 ms: 6 and 7 ms are due at once
        if (t == 8000) clock.advance_us(600);   // this one 0.6 ms: 0.4 ms left before the next
        return true;
      },
      [&] {
        events.push_back(-1);
        clock.advance_us(300);  // the idle work takes 0.3 ms of the wait
      });
  loop.run(std::stop_token{}, 10);
  const std::vector<std::int64_t> want = {0, -1, 1000, -1, 2000, -1, 3000, -1, 4000, -1, 5000, 6000, 7000, -1, 8000, 9000, -1};
  EXPECT_EQ(events, want);
  EXPECT_EQ(loop.dropped(), 0);
}

TEST(HapticThread, StartsAndStopsOnItsOwnThread) {
  VirtualClock clock;
  std::atomic<std::int64_t> seen{0};
  HapticThread loop(clock, 1000, [&](std::int64_t t) {
    seen.store(t);
    return t < 2'000'000;  // ends itself after 2 s of virtual time
  });
  loop.start();
  while (!loop.finished()) std::this_thread::yield();
  loop.stop();
  EXPECT_EQ(seen.load(), 2'000'000);
  EXPECT_EQ(loop.ticks(), 2001);
}

}  // namespace
}  // namespace cathbox::session
