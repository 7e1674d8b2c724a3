#include "session/event_log.hpp"

#include <gtest/gtest.h>

#include <string>
#include <thread>

namespace cathbox::session {
namespace {

TEST(EventLog, KeepsOrderCutsLongTextAndCountsWhatDoesNotFit) {
  EventLog log;
  const std::string long_text(500, 'x');
  EXPECT_TRUE(log.push(1, long_text.c_str()));
  for (std::size_t i = 1; i < EventLog::kCapacity; ++i) EXPECT_TRUE(log.push(static_cast<std::int64_t>(i), "e"));
  EXPECT_FALSE(log.push(999, "overflow"));
  EXPECT_EQ(log.lost(), 1U);
  LogEvent e;
  ASSERT_TRUE(log.pop(e));
  EXPECT_EQ(e.time_us, 1);
  EXPECT_EQ(std::string(e.text.data()).size(), e.text.size() - 1);
  for (std::size_t i = 1; i < EventLog::kCapacity; ++i) {
    ASSERT_TRUE(log.pop(e));
    EXPECT_EQ(e.time_us, static_cast<std::int64_t>(i));
  }
  EXPECT_FALSE(log.pop(e));
}

TEST(EventLog, ConcurrentProducerAndConsumerLoseNothingThatWasAccepted) {
  EventLog log;
  constexpr std::int64_t kCount = 100000;
  std::atomic<std::int64_t> accepted{0};
  std::atomic<bool> done{false};
  std::jthread producer([&] {
    for (std::int64_t i = 0; i < kCount; ++i) {
      if (log.push(i, "tick")) accepted.fetch_add(1);
    }
    done.store(true);
  });
  std::int64_t got = 0;
  std::int64_t last = -1;
  LogEvent e;
  for (;;) {
    const bool finished = done.load();  // read before popping: nothing can follow a failed pop
    if (log.pop(e)) {
      ASSERT_GT(e.time_us, last);
      last = e.time_us;
      ++got;
    } else if (finished) {
      break;
    }
  }
  EXPECT_EQ(got, accepted.load());
  EXPECT_EQ(got + static_cast<std::int64_t>(log.lost()), kCount);
}

}  // namespace
}  // namespace cathbox::session
