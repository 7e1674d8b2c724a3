// ProgramHand: a program's speeds into the whole micrometres and microradians a session takes.
#include "session/program_hand.hpp"

#include <gtest/gtest.h>

namespace cathbox::session {
namespace {

TickInput input(std::size_t tools, std::int64_t max_um) {
  TickInput in;
  in.tool_count = tools;
  for (std::size_t t = 0; t < tools; ++t) in.max_insertion_um[t] = max_um;
  return in;
}

TEST(ProgramHand, SpeedsIntegrateOverTheTickIntoWholeUnits) {
  ProgramHand hand(1e-3, "test");
  EXPECT_EQ(hand.kind(), HandKind::kProgram);
  EXPECT_STREQ(hand_kind_name(hand.kind()), "program");
  TickInput in = input(2, 1'000'000);
  hand.set_speed(0, {10.0, 0.5});
  hand.set_speed(1, {-3.0, -1.0});
  for (int i = 0; i < 100; ++i) hand.read(i, in);
  EXPECT_EQ(in.tools[0].insertion_um, 1'000);  // 10 mm/s for 0.1 s
  EXPECT_EQ(in.tools[0].rotation_urad, 50'000);
  EXPECT_EQ(in.tools[1].insertion_um, 0);  // pulled back from the entry: held at 0
  EXPECT_EQ(in.tools[1].rotation_urad, -100'000);
}

TEST(ProgramHand, KeepsTheFractionsOfSlowSpeeds) {
  ProgramHand hand(1e-3, "test");
  TickInput in = input(1, 1'000'000);
  hand.set_speed(0, {0.25, 0.0});  // a quarter of a micrometre per tick
  const std::int64_t expected[] = {0, 1, 1, 1, 1, 2, 2, 2};  // llround(0.25 k)
  for (int i = 0; i < 8; ++i) {
    hand.read(i, in);
    EXPECT_EQ(in.tools[0].insertion_um, expected[i]) << "tick " << i;
  }
  for (int i = 8; i < 400; ++i) hand.read(i, in);
  EXPECT_EQ(in.tools[0].insertion_um, 100);
}

TEST(ProgramHand, ClampsTheInsertionWithoutADeadZone) {
  ProgramHand hand(1e-3, "test");
  TickInput in = input(1, 500);
  hand.set_speed(0, {10.0, 0.0});
  for (int i = 0; i < 100; ++i) hand.read(i, in);
  EXPECT_EQ(in.tools[0].insertion_um, 500);  // 1000 um asked, 500 the most
  hand.set_speed(0, {-10.0, 0.0});
  for (int i = 0; i < 10; ++i) hand.read(i, in);
  EXPECT_EQ(in.tools[0].insertion_um, 400);  // back from the limit at once
}

TEST(ProgramHand, CarriesOnFromWhereTheToolsAreAndFromARestart) {
  ProgramHand hand(1e-3, "test");
  TickInput in = input(1, 1'000'000);
  in.tools[0] = {300, 7};
  hand.read(0, in);
  EXPECT_EQ(in.tools[0], (ToolCommand{300, 7}));
  hand.restart(0, {200, 0});  // a new device at the hub
  hand.set_speed(0, {1.0, 0.0});
  hand.read(1, in);
  EXPECT_EQ(in.tools[0], (ToolCommand{201, 0}));
}

}  // namespace
}  // namespace cathbox::session
