// The tool's local force law as a box command, checked with the protocol's own evaluator (the
// same arithmetic the firmware runs at >= 10 kHz).
#include "device/force_law_command.hpp"

#include <gtest/gtest.h>

#include "base/force_law.hpp"

namespace cathbox::device {
namespace {

TEST(ForceLawCommand, TheBoxPushesBackWhatTheToolResists) {
  base::ForceLaw law;
  law.insertion0_mm = 30.0;        // in the box's frame: 30 mm from its count zero
  law.force0_mN = 100.0;           // the tool resists insertion with 100 mN here
  law.stiffness_mN_per_mm = 50.0;  // and 50 mN more per mm deeper
  law.damping_mN_s_per_mm = 2.0;
  law.rotation0_rad = 0.0;
  law.torque0_mNmm = 3.0;
  law.torsion_stiffness_mNmm_per_rad = 4.0;
  const cbx_command_report c = force_law_command(law, CBX_MODE_BRAKE);
  EXPECT_EQ(c.mode, CBX_MODE_BRAKE);
  ASSERT_EQ(cbx_force_law_check(&c.insertion), CBX_OK);
  ASSERT_EQ(cbx_force_law_check(&c.rotation), CBX_OK);
  // At the law's own point: the box pulls back with 100 mN.
  EXPECT_EQ(cbx_force_law_eval(&c.insertion, 30'000, 0), -100);
  // 1 mm deeper: 150 mN back; moving in at 10 mm/s adds 20 mN of damping.
  EXPECT_EQ(cbx_force_law_eval(&c.insertion, 31'000, 0), -150);
  EXPECT_EQ(cbx_force_law_eval(&c.insertion, 30'000, 10'000), -120);
  // Rotation: 3 uN m back at 0 rad, 4 more one radian further.
  EXPECT_EQ(cbx_force_law_eval(&c.rotation, 0, 0), -3);
  EXPECT_EQ(cbx_force_law_eval(&c.rotation, 1'000'000, 0), -7);
}

TEST(ForceLawCommand, NegativeGainsFromTheSolverAreNotSentAndHugeValuesSaturate) {
  base::ForceLaw law;
  law.stiffness_mN_per_mm = -5.0;
  law.damping_mN_s_per_mm = -1.0;
  law.force0_mN = 1e12;
  law.insertion0_mm = -1e300;
  const cbx_command_report c = force_law_command(law, CBX_MODE_MOTOR);
  EXPECT_EQ(c.insertion.stiffness, 0);
  EXPECT_EQ(c.insertion.damping, 0);
  EXPECT_EQ(c.insertion.offset, INT32_MIN);
  EXPECT_EQ(c.insertion.pos0, INT32_MIN);
  EXPECT_EQ(cbx_force_law_check(&c.insertion), CBX_OK);
}

TEST(ForceLawCommand, OutputsOff) {
  EXPECT_EQ(outputs_off_command().mode, CBX_MODE_OFF);
}

}  // namespace
}  // namespace cathbox::device
