// BoxClient's per-tick calls (poll, send) allocate nothing once connected: the trainer calls
// them from its 1 kHz haptic thread. Counted with a replaced global operator new that counts
// only while the client's calls run.
#include <gtest/gtest.h>

#include <cstdlib>
#include <new>

#include "emu_world.hpp"

namespace {
thread_local bool counting = false;
thread_local uint64_t allocations = 0;
}  // namespace

// The replacement pair allocates with malloc and frees with free, which GCC cannot see.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void* operator new(std::size_t size) {
  if (counting) ++allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

namespace cathbox::testing {
namespace {

TEST(HapticTick, PollAndSendAllocateNothing) {
  EmuWorld world;
  world.emu().set_hand(0, emu::HandScript::parse("v:10mm/s:5s").value());
  auto client = world.connect();
  const auto command = wall_command(20'000, 1'000'000);
  device::BoxState state;
  uint64_t updates = 0;
  for (int ms = 0; ms < 2000; ++ms) {
    world.advance(1000);
    counting = true;
    updates += client->poll(state) ? 1u : 0u;
    const bool sent = client->send(command);
    counting = false;
    ASSERT_TRUE(sent);
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(updates, 1990u);
}

}  // namespace
}  // namespace cathbox::testing
