// The one mapping between box counts, calibrated micrometres and the session's tools: round
// trips in every direction, taking another tool, the keyboard's nudges, the force law's frame.
#include "session/hand_mapping.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace cathbox::session {
namespace {

// The emulated box's own calibration (hw-sim/README.md): 108 650 counts/m, 4096 counts/rev.
const EncoderCalibration kEmu{108'650, 4096};

TEST(HandMapping, CountsToMicrometresAndBackRoundTripForEveryCount) {
  const HandMapping m(kEmu);
  for (std::int64_t c = -200'000; c <= 200'000; c += 7) {
    ASSERT_EQ(m.insertion_counts_from_um(m.insertion_um_from_counts(c)), c) << c;
    ASSERT_EQ(m.rotation_counts_from_urad(m.rotation_urad_from_counts(c)), c) << c;
  }
  // 108 650 counts are one metre; 4096 counts one turn.
  EXPECT_EQ(m.insertion_um_from_counts(108'650), 1'000'000);
  EXPECT_EQ(m.insertion_um_from_counts(-1), -9);  // 9.204 um per count, rounded
  EXPECT_EQ(m.rotation_urad_from_counts(4096), std::llround(2.0 * M_PI * 1e6));
}

// What `cathbox monitor` shows: unrounded mm and rad (and per second) that agree with the
// rounded micrometres / microradians, and 0 without a calibration.
TEST(HandMapping, DisplayUnitsAgreeWithTheRoundedOnes) {
  const HandMapping m(kEmu);
  EXPECT_DOUBLE_EQ(m.insertion_mm_from_counts(108'650), 1000.0);
  EXPECT_DOUBLE_EQ(m.rotation_rad_from_counts(-2048), -M_PI);
  for (std::int64_t c = -50'000; c <= 50'000; c += 313) {
    EXPECT_NEAR(m.insertion_mm_from_counts(static_cast<double>(c)) * 1000.0, m.insertion_um_from_counts(c), 0.5) << c;
    EXPECT_NEAR(m.rotation_rad_from_counts(static_cast<double>(c)) * 1e6, m.rotation_urad_from_counts(c), 0.5) << c;
  }
  const HandMapping none;
  EXPECT_EQ(none.insertion_mm_from_counts(1000), 0.0);
  EXPECT_EQ(none.rotation_rad_from_counts(1000), 0.0);
}

TEST(HandMapping, HandPositionsCountFromTheOriginAndRoundTrip) {
  HandMapping m(kEmu);
  EXPECT_EQ(m.hand_from_counts({5000, 300}), (HandPosition{0, 0}));  // no origin yet: still
  m.set_count_origin({123'456, -2000});
  EXPECT_EQ(m.hand_from_counts({123'456, -2000}), (HandPosition{0, 0}));
  for (std::int64_t d = -50'000; d <= 50'000; d += 13) {
    const BoxCounts counts{123'456 + d, -2000 - d / 3};
    ASSERT_EQ(m.counts_from_hand(m.hand_from_counts(counts)), counts) << d;
  }
  // 10 mm in: 1086.5 counts, so the hand reads within half a count of 10 mm.
  EXPECT_NEAR(static_cast<double>(m.hand_from_counts({123'456 + 1087, -2000}).insertion_um), 10'000.0, 5.0);
}

TEST(HandMapping, TakingAnotherToolCarriesOnFromWhereThatToolIs) {
  HandMapping m;  // no encoders: positions in um already
  EXPECT_EQ(m.command({2000, 100}), (ToolCommand{2000, 100}));  // tool 0 follows the hand
  m.hold(1, ToolCommand{50'000, 7});                            // tool 1 is 50 mm in
  EXPECT_EQ(m.held(), 1U);
  EXPECT_EQ(m.command({2000, 100}), (ToolCommand{50'000, 7}));  // the hand has not moved
  EXPECT_EQ(m.command({2500, 90}), (ToolCommand{50'500, -3}));  // 0.5 mm on, 10 urad back
  m.hold(0, ToolCommand{2000, 100});                            // back to tool 0 where it stayed
  EXPECT_EQ(m.command({2500, 90}), (ToolCommand{2000, 100}));
  EXPECT_EQ(m.command({3000, 90}), (ToolCommand{2500, 100}));
}

TEST(HandMapping, KeyboardNudgesStayWithinTheToolsRange) {
  HandMapping m;
  (void)m.command({0, 0});
  m.nudge(3000, 500, 10'000);
  EXPECT_EQ(m.command({0, 0}), (ToolCommand{3000, 500}));
  m.nudge(-5000, 0, 10'000);  // pulling below 0 stops at 0 ...
  EXPECT_EQ(m.command({0, 0}).insertion_um, 0);
  m.nudge(1000, 0, 10'000);   // ... so pushing again moves at once (no dead zone)
  EXPECT_EQ(m.command({0, 0}).insertion_um, 1000);
  m.nudge(20'000, 0, 10'000);
  EXPECT_EQ(m.command({0, 0}).insertion_um, 10'000);
}

TEST(HandMapping, TheForceLawGoesIntoTheBoxsFrame) {
  HandMapping m(kEmu);
  m.set_count_origin({108'650 / 50, 0});  // the box read 20 mm when the session started
  (void)m.command({5000, 0});             // the hand pushed 5 mm since
  m.hold(1, ToolCommand{40'000, 1'000'000});  // and holds tool 1: 40 mm in, 1 rad
  tool::ForceLaw law;
  law.insertion0_mm = 41.0;  // around 1 mm further in the session
  law.rotation0_rad = 1.5;
  law.stiffness_mN_per_mm = 3.0;
  const tool::ForceLaw box = m.law_to_box(law);
  // Box frame = session - offset + origin: 41 - (40 - 5) + 20 = 26 mm; 1.5 - (1 - 0) + 0 rad.
  EXPECT_NEAR(box.insertion0_mm, 26.0, 1e-3);
  EXPECT_NEAR(box.rotation0_rad, 0.5, 1e-6);
  EXPECT_DOUBLE_EQ(box.stiffness_mN_per_mm, 3.0);
  // And back: where the box reads 26 mm, the session has tool 1 at 41 mm.
  const HandPosition at26 = m.hand_from_counts({m.insertion_counts_from_um(26'000), 0});
  EXPECT_NEAR(static_cast<double>(m.command(at26).insertion_um), 41'000.0, 10.0);
}

}  // namespace
}  // namespace cathbox::session
