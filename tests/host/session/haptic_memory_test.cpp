#include "session/haptic_memory.hpp"

#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cstddef>
#include <cstdlib>

namespace cathbox::session {
namespace {

long minor_faults() {
  rusage u{};
  getrusage(RUSAGE_THREAD, &u);
  return u.ru_minflt;
}

void* volatile g_block = nullptr;  // the block escapes: the allocation is not optimised away

// Allocates `bytes`, writes a byte on each of its pages, frees it.
void touch_and_free(std::size_t bytes) {
  g_block = std::malloc(bytes);
  ASSERT_NE(g_block, nullptr);
  auto* bytes_at = static_cast<volatile unsigned char*>(g_block);
  for (std::size_t i = 0; i < bytes; i += 4096) bytes_at[i] = 1;
  std::free(g_block);
  g_block = nullptr;
}

// glibc maps a block this size afresh and unmaps it when freed (the first time; then it raises
// its threshold but still takes the next one from fresh heap pages): 4,096 page faults again.
// Kept, the second block is the first one's pages.
TEST(HapticMemory, AFreedBlockIsServedAgainFromPagesAlreadyFaultedIn) {
  keep_freed_memory();
  constexpr std::size_t kBytes = std::size_t{16} << 20;
  touch_and_free(kBytes);
  const long before = minor_faults();
  touch_and_free(kBytes);
  EXPECT_LT(minor_faults() - before, 64) << "of " << kBytes / 4096 << " pages";
}

}  // namespace
}  // namespace cathbox::session
