// 60 s of virtual time at 1 kHz: the host reads the newest state and sends one command per
// millisecond; the box (firmware core in cathbox-emu) renders a brake wall against a hand that
// pushes into it. No command is lost or reordered: the box's sequence echo advances by exactly
// one per state report.
#include <gtest/gtest.h>

#include "emu_world.hpp"

namespace cathbox::testing {
namespace {

TEST(ClosedLoop, SixtySecondsAtOneKilohertzWithSequenceEcho) {
  EmuWorld world;
  // The hand advances the tool at 10 mm/s for 3 s (into the wall at 20 mm), then leans on
  // it with 1 N for the rest of the minute.
  world.emu().set_hand(0, emu::HandScript::parse("v:10mm/s:3s,f:1000mN:57s").value());
  auto client = world.connect();
  const auto command = wall_command(20'000, 2'000'000);  // 2000 N/m

  device::BoxState state;
  bool have_echo = false;
  uint16_t last_echo = 0;
  uint64_t echo_steps = 0;
  uint64_t echo_violations = 0;
  int32_t max_force_mN = 0;
  for (int ms = 0; ms < 60'000; ++ms) {
    world.advance(1000);
    if (client->poll(state)) {
      const uint16_t echo = state.report.command_seq_echo;
      if (have_echo) {
        const uint16_t delta = static_cast<uint16_t>(echo - last_echo);
        if (delta == 1) {
          ++echo_steps;
        } else {
          ++echo_violations;
        }
      }
      // The echo is valid once the first command was applied (sent at ms 0, applied by ms 2).
      have_echo = ms >= 3;
      last_echo = echo;
      max_force_mN = std::min(max_force_mN, state.report.insertion_force_mN);
    }
    ASSERT_TRUE(client->send(command));
  }
  const auto& stats = client->stats();
  EXPECT_EQ(stats.commands_sent, 60'000u);
  EXPECT_EQ(stats.commands_dropped, 0u);
  EXPECT_EQ(world.emu().out_reports_delivered(), 60'000u - 1u);  // the last one is still in flight
  EXPECT_EQ(stats.states_missed, 0u);
  EXPECT_EQ(stats.rejected(), 0u);
  EXPECT_EQ(echo_violations, 0u);
  EXPECT_GT(echo_steps, 59'990u);
  EXPECT_EQ(state.report.rx_errors, 0u);
  EXPECT_EQ(state.report.faults, 0u);
  // The wall held: the hand's grip (400 N/m) pushed the tool to where it balances the wall
  // (2000 N/m): 20 + 10 * 400 / 2400 = 21.7 mm; leaning on it with 1 N afterwards, the brake
  // holds it there. It pushed back with over 0.5 N.
  const double pos_mm = world.emu().model().state(0).pos * 1e3;
  EXPECT_GT(pos_mm, 21.3);
  EXPECT_LT(pos_mm, 22.0);
  EXPECT_LT(max_force_mN, -500);
}

}  // namespace
}  // namespace cathbox::testing
