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
  model.params(0).friction_damping = 0;
  model.set_script(0, HandScript({{1'000'000, HandMode::kForce, 0.5}}), 0);
  uint64_t t = 0;
  run(model, 0.1, {0, 0}, t);
  const double m = model.params(0).mass;
  EXPECT_NEAR(model.state(0).vel, 0.5 / m * 0.1, 1e-3);
  EXPECT_NEAR(model.state(0).pos, 0.5 * 0.5 / m * 0.01, 1e-4);
  EXPECT_EQ(model.state(0).count, static_cast<int64_t>(std::floor(model.state(0).pos * model.params(0).counts_per_unit)));
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
  auto s = HandScript::parse("v:0.02:2s,f:-1.5:500ms,free:100us");
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s.value().at(0).mode, HandMode::kVelocity);
  EXPECT_DOUBLE_EQ(s.value().at(1'999'999).value, 0.02);
  EXPECT_EQ(s.value().at(2'000'000).mode, HandMode::kForce);
  EXPECT_DOUBLE_EQ(s.value().at(2'400'000).value, -1.5);
  EXPECT_EQ(s.value().at(2'500'050).mode, HandMode::kFree);
  EXPECT_EQ(s.value().at(9'000'000).mode, HandMode::kFree);
  for (const char* bad : {"v:1", "x:1:1s", "v:abc:1s", "v:1:1", "v:1:-1s", "free:1s:2", "f:nan:1s"}) {
    auto parsed = HandScript::parse(bad);
    ASSERT_FALSE(parsed.ok()) << bad;
    EXPECT_NE(parsed.error().message.find("segment 1"), std::string::npos) << parsed.error().message;
  }
  auto second = HandScript::parse("v:1:1s,zz");
  ASSERT_FALSE(second.ok());
  EXPECT_NE(second.error().message.find("segment 2"), std::string::npos);
}

}  // namespace
}  // namespace cathbox::emu
