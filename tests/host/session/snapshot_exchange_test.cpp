#include "session/snapshot_exchange.hpp"

#include <gtest/gtest.h>

#include <thread>

#include "session/scene_snapshot.hpp"

namespace cathbox::session {
namespace {

TEST(SnapshotExchange, ReaderSeesNothingUntilTheFirstPublish) {
  SnapshotExchange<int> x(0);
  EXPECT_FALSE(x.acquire());
  x.write_slot() = 7;
  x.publish();
  EXPECT_TRUE(x.acquire());
  EXPECT_EQ(x.read_slot(), 7);
  EXPECT_FALSE(x.acquire());  // nothing newer
  EXPECT_EQ(x.read_slot(), 7);
}

TEST(SnapshotExchange, ReaderGetsTheNewestOfSeveralPublishes) {
  SnapshotExchange<int> x(0);
  for (int i = 1; i <= 5; ++i) {
    x.write_slot() = i;
    x.publish();
  }
  EXPECT_TRUE(x.acquire());
  EXPECT_EQ(x.read_slot(), 5);
}

TEST(SnapshotExchange, WriterNeverWritesTheSlotTheReaderHolds) {
  SnapshotExchange<int> x(0);
  x.write_slot() = 1;
  x.publish();
  ASSERT_TRUE(x.acquire());
  const int* held = &x.read_slot();
  for (int i = 2; i < 10; ++i) {
    EXPECT_NE(&x.write_slot(), held);
    x.write_slot() = i;
    x.publish();
  }
  EXPECT_EQ(*held, 1);
}

TEST(SnapshotExchange, PublishingAReservedSnapshotDoesNotAllocate) {
  SnapshotExchange<SceneSnapshot> x;
  x.prepare_slots([](SceneSnapshot& s) { s.reserve(300); });
  for (int round = 0; round < 6; ++round) {
    SceneSnapshot& s = x.write_slot();
    const auto* before = s.tools[0].nodes_mm.data();
    s.tools[0].nodes_mm.assign(250, glm::vec3(1.0F));
    EXPECT_EQ(s.tools[0].nodes_mm.data(), before);
    x.publish();
  }
}

// Two threads: every snapshot the reader sees is internally consistent (never torn) and the
// sequence it observes never goes backwards.
TEST(SnapshotExchange, ConcurrentReaderSeesWholeMonotonicSnapshots) {
  struct Pair {
    std::int64_t a = 0;
    std::int64_t b = 0;
  };
  SnapshotExchange<Pair> x;
  constexpr std::int64_t kCount = 200000;
  std::jthread writer([&] {
    for (std::int64_t i = 1; i <= kCount; ++i) {
      x.write_slot() = Pair{i, -i};
      x.publish();
    }
  });
  std::int64_t last = 0;
  while (last < kCount) {
    if (x.acquire()) {
      const Pair& p = x.read_slot();
      ASSERT_EQ(p.a, -p.b);
      ASSERT_GE(p.a, last);
      last = p.a;
    }
  }
  EXPECT_EQ(last, kCount);
}

}  // namespace
}  // namespace cathbox::session
