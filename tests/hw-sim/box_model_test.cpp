// The physical model against analytic references: a constant force accelerates the tool as
// F/m; a brake at full drive stops it; a motor pushes it; the hand follows its script.
#include <gtest/gtest.h>

#include <cmath>

#include "emu/box_model.hpp"

namespace cathbox::emu {
namespace {

constexpr double kDt = 10e-6;

void run(BoxModel& model, double seconds, std::array<int16_t, 2> drive, uint64_t& t_us) {
  std::array<int64_t, 2> steps{};
  for (int i = 0; i < static_cast<int>(seconds / kDt + 0.5); ++i) {
    t_us += 10;
    model.step(kDt, t_us, drive, steps);
  }
}

TEST(BoxModel, ConstantHandForceAcceleratesAsForceOverMassWithFriction) {
  BoxModel model;
  model.params(0).friction_damping = 0;  // only the Coulomb part: (F - Fc) / (m_mechanism + m_tool)
  model.set_script(0, HandScript({{1'000'000, HandMode::kForce, 0.5}}), 0);
  uint64_t t = 0;
  run(model, 0.1, {0, 0}, t);
  const double m = model.params(0).mass + model.params(0).tool_mass;
  const double a = (0.5 - model.params(0).friction_coulomb) / m;
  EXPECT_NEAR(model.state(0).vel, a * 0.1, 1e-3);
  EXPECT_NEAR(model.state(0).pos, 0.5 * a * 0.01, 1e-4);
  EXPECT_EQ(model.state(0).count, static_cast<int64_t>(std::floor(model.state(0).pos * model.params(0).counts_per_unit)));
}

// The rollers' and the collet's friction (hw-sim/README.md): a hand force below it does not move
// the tool; above it, the tool moves.
TEST(BoxModel, RollerAndColletFrictionHoldUntilTheHandOvercomesThem) {
  BoxModel model;
  ASSERT_GE(model.params(0).friction_coulomb, 0.2);
  ASSERT_GE(model.params(1).friction_coulomb, 0.5e-3);
  model.set_script(0, HandScript({{500'000, HandMode::kForce, 0.8 * model.params(0).friction_coulomb},
                                  {500'000, HandMode::kForce, 1.5 * model.params(0).friction_coulomb}}), 0);
  model.set_script(1, HandScript({{500'000, HandMode::kForce, 0.8 * model.params(1).friction_coulomb},
                                  {500'000, HandMode::kForce, 1.5 * model.params(1).friction_coulomb}}), 0);
  uint64_t t = 0;
  run(model, 0.49, {0, 0}, t);
  EXPECT_EQ(model.state(0).count, 0);
  EXPECT_EQ(model.state(1).count, 0);
  EXPECT_EQ(model.state(0).vel, 0.0);
  EXPECT_EQ(model.state(1).vel, 0.0);
  run(model, 0.5, {0, 0}, t);
  EXPECT_GT(model.state(0).count, 100);
  EXPECT_GT(model.state(1).count, 20);
}

// `cathbox-emu --motor --hand-insertion v:30mm/s:9s,f:-2000mN:6s`: in at 30 mm/s for 9 s (270 mm), then
// pulled out with 2 N. The tool leaves the rollers at its start: the encoder stops near 0 mm
// (the rollers coast to rest) instead of following the hand metres further.
TEST(BoxModel, AToolWithdrawnPastItsStartLeavesTheRollers) {
  BoxModel model;
  model.params(0).motor = true;
  model.set_script(0, HandScript({{9'000'000, HandMode::kVelocity, 0.03}, {6'000'000, HandMode::kForce, -2.0}}), 0);
  uint64_t t = 0;
  run(model, 9.0, {0, 0}, t);
  EXPECT_NEAR(model.state(0).pos, 0.27, 0.002);
  EXPECT_TRUE(model.engaged());
  run(model, 6.0, {0, 0}, t);
  EXPECT_FALSE(model.engaged());
  EXPECT_LT(model.state(0).tool_pos, 0.0);
  const double reading_mm = model.state(0).count / model.params(0).counts_per_unit * 1e3;
  EXPECT_GT(reading_mm, -20.0);  // the rollers' coast after the tool left (0 before: -5658 mm)
  EXPECT_LE(reading_mm, 0.0);
  EXPECT_EQ(model.state(0).vel, 0.0);  // friction stopped them
}

// Pulled out briefly, then pushed back in: the rollers take the tool up again and count.
TEST(BoxModel, AToolPushedBackInIsTakenUpByTheRollers) {
  BoxModel model;
  model.set_script(0, HandScript({{1'000'000, HandMode::kVelocity, 0.05}, {300'000, HandMode::kForce, -2.0},
                                  {5'000'000, HandMode::kVelocity, 0.0}}), 0);
  uint64_t t = 0;
  run(model, 1.3, {0, 0}, t);
  ASSERT_FALSE(model.engaged());
  const double out_m = model.state(0).tool_pos;
  ASSERT_LT(out_m, -0.05);
  model.set_script(0, HandScript({{3'000'000, HandMode::kVelocity, 0.1}}), t);
  const int64_t before = model.state(0).count;
  run(model, 2.9, {0, 0}, t);
  EXPECT_TRUE(model.engaged());
  // Counted: the part of 0.29 m travelled between the rollers.
  const double counted_m = (model.state(0).count - before) / model.params(0).counts_per_unit;
  EXPECT_NEAR(counted_m, model.state(0).tool_pos, 0.005);
  EXPECT_GT(counted_m, 0.29 + out_m - 0.01);
}

// Insertion stops at the tool's length: its hub reaches the rollers, the hand pushes on.
TEST(BoxModel, InsertionIsBoundedByTheToolsLength) {
  BoxModel model;
  model.set_script(0, HandScript({{5'000'000, HandMode::kVelocity, 0.5}}), 0);
  uint64_t t = 0;
  run(model, 4.0, {0, 0}, t);
  EXPECT_NEAR(model.state(0).tool_pos, model.params(0).travel, 1e-9);
  EXPECT_NEAR(model.state(0).pos, BoxModel::kToolLength, 1e-6);
  EXPECT_EQ(model.state(0).vel, 0.0);
  EXPECT_GT(model.state(0).hand_force, 50.0);  // the grip compressed against the hub
}

// A motor spinning rollers that hold no tool: the encoder counts the rollers, the tool is gone.
TEST(BoxModel, AMotorSpinsTheRollersAloneOnceTheToolIsOut) {
  BoxModel model;
  model.params(0).motor = true;
  model.set_script(0, HandScript({{100'000, HandMode::kVelocity, -0.1}}), 0);
  uint64_t t = 0;
  run(model, 0.1, {0, 0}, t);
  ASSERT_FALSE(model.engaged());
  run(model, 0.2, {400, 0}, t);  // 2 N inward on the rollers alone
  EXPECT_GT(model.state(0).vel, 0.5);
  EXPECT_GT(model.state(0).count, 0.05 * model.params(0).counts_per_unit);
  EXPECT_LT(model.state(0).tool_pos, 0.0);  // the tool stays out: the rollers do not pull it in
  EXPECT_FALSE(model.engaged());
}

TEST(BoxModel, BrakeHoldsAgainstAWeakerHandAndSlipsUnderAStrongerOne) {
  BoxModel model;  // brake, full scale 5 N
  model.set_script(0, HandScript({{1'000'000, HandMode::kForce, 2.0}}), 0);
  uint64_t t = 0;
  run(model, 0.2, {500, 0}, t);  // 2.5 N of brake against 2 N
  EXPECT_EQ(model.state(0).vel, 0.0);
  EXPECT_EQ(model.state(0).count, 0);
  model.set_script(0, HandScript({{1'000'000, HandMode::kForce, 4.0}}), t);
  run(model, 0.2, {500, 0}, t);  // 4 N against 2.5 N: moves
  EXPECT_GT(model.state(0).vel, 0.5);
  EXPECT_NEAR(model.state(0).actuator_force, -2.5, 1e-9);
}

TEST(BoxModel, MotorPushesAToolNobodyHolds) {
  BoxModel model;
  model.params(0).motor = true;
  uint64_t t = 0;
  run(model, 0.05, {-200, 0}, t);  // 1 N outward
  EXPECT_LT(model.state(0).vel, 0.0);
  EXPECT_LT(model.state(0).count, 0);
}

TEST(BoxModel, HandFollowsAVelocityScript) {
  BoxModel model;
  model.set_script(1, HandScript({{2'000'000, HandMode::kVelocity, 3.0}, {500'000, HandMode::kVelocity, 0.0}}), 0);
  uint64_t t = 0;
  run(model, 2.5, {0, 0}, t);
  EXPECT_NEAR(model.state(1).pos, 6.0, 0.05);  // 2 s at 3 rad/s
  EXPECT_NEAR(model.current_mA(1, 500), 500, 1);
}

TEST(HandScript, ParsesSegmentsAndRefusesBadOnes) {
  auto s = HandScript::parse("v:20mm/s:2s,f:-1500mN:500ms,free:100us");
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s.value().at(0).mode, HandMode::kVelocity);
  EXPECT_DOUBLE_EQ(s.value().at(1'999'999).value, 0.02);
  EXPECT_EQ(s.value().at(2'000'000).mode, HandMode::kForce);
  EXPECT_DOUBLE_EQ(s.value().at(2'400'000).value, -1.5);
  EXPECT_EQ(s.value().at(2'500'050).mode, HandMode::kFree);
  EXPECT_EQ(s.value().at(9'000'000).mode, HandMode::kFree);
  for (const char* bad : {"v:1mm/s", "x:1mm/s:1s", "v:abcmm/s:1s", "v:1mm/s:1", "v:1mm/s:-1s", "free:1s:2", "f:nanmN:1s"}) {
    auto parsed = HandScript::parse(bad);
    ASSERT_FALSE(parsed.ok()) << bad;
    EXPECT_NE(parsed.error().message.find("segment 1"), std::string::npos) << parsed.error().message;
  }
  auto second = HandScript::parse("v:1mm/s:1s,zz");
  ASSERT_FALSE(second.ok());
  EXPECT_NE(second.error().message.find("segment 2"), std::string::npos);
}

// Values carry the project's units (mm/s, mN; rad/s, mNmm), converted to the model's SI. The
// old scripts in bare m/s and N are refused with one line, never read as mm/s or mN.
TEST(HandScript, ValuesCarryTheirUnitsAndOldScriptsAreRefused) {
  auto rot = HandScript::parse("v:3.14rad/s:2s,f:5mNmm:1s", 1);
  ASSERT_TRUE(rot.ok()) << rot.error().message;
  EXPECT_DOUBLE_EQ(rot.value().at(0).value, 3.14);
  EXPECT_DOUBLE_EQ(rot.value().at(2'000'000).value, 5e-6);
  for (const char* old : {"v:0.03:9s,f:-2:6s", "f:1.0:10s", "v:0.02m/s:1s", "f:2N:1s"}) {
    auto parsed = HandScript::parse(old);
    ASSERT_FALSE(parsed.ok()) << old;
    EXPECT_NE(parsed.error().message.find("segment 1"), std::string::npos) << parsed.error().message;
    EXPECT_NE(parsed.error().message.find("unit"), std::string::npos) << parsed.error().message;
    EXPECT_EQ(parsed.error().message.find('\n'), std::string::npos);
  }
  EXPECT_FALSE(HandScript::parse("v:20mm/s:1s", 1).ok());          // an insertion unit on rotation
  EXPECT_FALSE(HandScript::parse("v:20mm/s:1s,f:5mNmm:1s").ok());  // two axes in one script
}

}  // namespace
}  // namespace cathbox::emu
