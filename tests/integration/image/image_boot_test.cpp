// The shipped image boots on the emulated STM32F411: clocks, board, the 10 kHz control tick,
// USB connect, its main loop asleep in WFI between interrupts, and the host's enumeration.
#include <gtest/gtest.h>

#include "image_world.hpp"

namespace cathbox::testing {
namespace {

TEST(ImageBoot, RunsItsControlTickSleepsAndEnumerates) {
  ImageWorld world;
  emu::ImageEmulator& box = world.emu();
  world.advance(200'000);  // clocks, 25 ms forced device mode, 100 ms attach debounce, enumeration
  ASSERT_EQ(box.error(), "");
  EXPECT_TRUE(box.machine().otg().connected());
  EXPECT_EQ(box.machine().watchdog_resets(), 0u);
  // SysTick at 96 MHz / 9600: the tick ran at 10 kHz from the end of main's set-up (~25 ms).
  EXPECT_GE(box.machine().ticks(), 1700u);
  EXPECT_LE(box.machine().ticks(), 2000u);
  EXPECT_GT(box.machine().tick_instructions_last(), 0u);
  // Asleep between interrupts: far fewer instructions than cycles.
  EXPECT_LT(box.machine().instructions(), box.machine().cycles() / 2);
  EXPECT_TRUE(box.enumerated()) << box.enumeration_error();
  EXPECT_EQ(box.machine().otg().address(), 1);
  EXPECT_FALSE(box.report_descriptor().empty());
}

}  // namespace
}  // namespace cathbox::testing
