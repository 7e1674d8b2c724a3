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

// The crystal does not start: the image gives up on HSE after its start-up loop, runs the PLL
// from the 16 MHz HSI and reports board fault HSE; a good crystal reports none.
TEST(ImageBoot, CrystalFailureFallsBackToHsiAndReportsTheBoardFault) {
  for (const bool fails : {false, true}) {
    ImageWorld world;
    world.emu().machine().inputs().crystal_fails = fails;
    world.advance(300'000);  // the HSE start-up loop (~20 ms) runs out first when it fails
    ASSERT_EQ(world.emu().error(), "");
    ASSERT_TRUE(world.emu().enumerated()) << world.emu().enumeration_error();
    auto client = world.connect();
    device::BoxState state;
    for (int ms = 0; ms < 20; ++ms) {
      world.advance(1000);
      (void)client->poll(state);
    }
    EXPECT_EQ(state.report.board_faults, fails ? static_cast<unsigned>(CBX_BOARD_FAULT_HSE) : 0u) << "crystal fails: " << fails;
    EXPECT_GE(world.emu().machine().ticks(), 2500u);  // the 10 kHz tick runs either way
  }
}

}  // namespace
}  // namespace cathbox::testing
