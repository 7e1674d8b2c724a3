#include "session/scripted_hand.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::session {
namespace {

HandObservation tip_at(glm::vec3 p, glm::vec3 dir = {1, 0, 0}, glm::vec3 bend = {0, 1, 0}) {
  HandObservation o;
  o.tip_mm = p;
  o.tip_direction = dir;
  o.tip_bend = bend;
  return o;
}

TEST(ScriptedHand, PushesStraightWhenTheTipIsAligned) {
  ScriptedHand hand({{0, 0, 0}, {100, 0, 0}}, 500.0);
  HandCommand c;
  for (int i = 0; i < 1000; ++i) c = hand.step(0.001, tip_at({static_cast<float>(i) * 0.015F, 0, 0}));
  EXPECT_NEAR(c.insertion_mm, 15.0, 1e-6);
  EXPECT_DOUBLE_EQ(c.rotation_rad, 0.0);
  EXPECT_EQ(hand.retries(), 0);
  EXPECT_NEAR(hand.path_length_mm(), 100.0, 1e-9);
}

TEST(ScriptedHand, TwistsTheBendTowardsThePathAheadAndSlowsDown) {
  // The path turns towards +Z; the bend points +Y: a quarter turn (positive about +X) is needed.
  ScriptedHand hand({{0, 0, 0}, {3, 0, 0}, {3, 0, 10}}, 500.0);
  const HandCommand c = hand.step(0.01, tip_at({0, 0, 0}));
  EXPECT_GT(c.rotation_rad, 0.0);
  EXPECT_NEAR(c.rotation_rad, 0.01 * 3.0, 1e-9);  // 4/s x 90 deg, clamped at 3 rad/s
  EXPECT_LT(c.insertion_mm, 0.01 * 15.0);
  // Bend already towards +Z: no twist.
  ScriptedHand aligned({{0, 0, 0}, {3, 0, 0}, {3, 0, 10}}, 500.0);
  EXPECT_NEAR(aligned.step(0.01, tip_at({0, 0, 0}, {1, 0, 0}, {0, 0, 1})).rotation_rad, 0.0, 1e-9);
  // The opposite convention twists the other way.
  ScriptedHandSettings s;
  s.rotation_sign = -1.0;
  ScriptedHand mirrored({{0, 0, 0}, {3, 0, 0}, {3, 0, 10}}, 500.0, s);
  EXPECT_LT(mirrored.step(0.01, tip_at({0, 0, 0})).rotation_rad, 0.0);
}

TEST(ScriptedHand, BacksOffAndTurnsWhenTheForceRises) {
  ScriptedHand hand({{0, 0, 0}, {100, 0, 0}}, 500.0);
  HandCommand c;
  for (int i = 0; i < 500; ++i) c = hand.step(0.001, tip_at({static_cast<float>(i) * 0.015F, 0, 0}));
  const double before = c.insertion_mm;
  HandObservation pushed = tip_at({7.5F, 0, 0});
  pushed.hand_force_mN = 400.0;
  c = hand.step(0.001, pushed);
  EXPECT_EQ(hand.retries(), 1);
  EXPECT_TRUE(hand.backing_off());
  for (int i = 0; i < 1000 && hand.backing_off(); ++i) c = hand.step(0.001, tip_at({7.5F, 0, 0}));
  EXPECT_FALSE(hand.backing_off());
  EXPECT_NEAR(c.insertion_mm, before + 0.015 - 6.0, 1e-6);
  EXPECT_NEAR(c.rotation_rad, 1.5707963, 1e-6);
}

TEST(ScriptedHand, BacksOffWhenTheTipMakesNoProgressAndGivesUpAfterFruitlessTries) {
  ScriptedHand hand({{0, 0, 0}, {100, 0, 0}}, 500.0);
  for (int i = 0; i < 999; ++i) (void)hand.step(0.001, tip_at({2, 0, 0}));
  EXPECT_EQ(hand.retries(), 0);
  for (int i = 0; i < 5; ++i) (void)hand.step(0.001, tip_at({2, 0, 0}));
  EXPECT_EQ(hand.retries(), 1);
  EXPECT_FALSE(hand.gave_up());
  // The tip never gets past x = 2: after 9 tries in a row that end no further, it stops.
  for (int i = 0; i < 30000 && !hand.gave_up(); ++i) (void)hand.step(0.001, tip_at({2, 0, 0}));
  EXPECT_TRUE(hand.gave_up());
  EXPECT_EQ(hand.retries(), 10);
}

// A kinematic toy: a trunk along +X splits at x = 20 into a branch up (+Z) and one down (-Z);
// the tip enters the branch its bend points to when it passes the junction, and the bend turns
// with the proximal rotation. The target is down, the bend starts up: the hand must turn it.
TEST(ScriptedHand, SteersAKinematicTipIntoTheTargetBranch) {
  std::vector<glm::vec3> path;
  for (int i = 0; i <= 20; ++i) path.emplace_back(static_cast<float>(i), 0.0F, 0.0F);
  for (int i = 1; i <= 20; ++i) path.emplace_back(20.0F + 0.7F * static_cast<float>(i), 0.0F, -0.7F * static_cast<float>(i));
  ScriptedHand hand(path, 200.0);
  int branch = 0;  // 0: trunk, +1 up, -1 down
  glm::vec3 tip{0.0F};
  glm::vec3 dir{1, 0, 0};
  glm::vec3 bend{0, 0, 1};
  for (int i = 0; i < 20000; ++i) {
    const HandCommand c = hand.step(0.001, tip_at(tip, dir, bend));
    const auto rot = static_cast<float>(c.rotation_rad);
    bend = glm::vec3(0.0F, -std::sin(rot), std::cos(rot));  // starts at +Z, turns about +X
    const auto ins = static_cast<float>(c.insertion_mm);
    if (ins <= 20.0F) {
      branch = 0;
      tip = {ins, 0.0F, 0.0F};
      dir = {1, 0, 0};
    } else {
      if (branch == 0) branch = bend.z >= 0.0F ? 1 : -1;
      const float s = (ins - 20.0F) * 0.7071F;
      tip = {20.0F + s, 0.0F, static_cast<float>(branch) * s};
      dir = glm::normalize(glm::vec3(1.0F, 0.0F, static_cast<float>(branch)));
    }
    if (glm::distance(tip, path.back()) < 1.0F) break;
  }
  EXPECT_EQ(branch, -1);
  EXPECT_LT(glm::distance(tip, path.back()), 1.0F);
}

}  // namespace
}  // namespace cathbox::session

namespace cathbox::session {
namespace {

// A hairpin: out along +X, back along -X 2 mm beside. A tip still on the way out but close to
// the way back must not make the hand believe it has gone round.
TEST(ScriptedHand, ProgressFollowsThePathAndDoesNotJumpAcrossAHairpin) {
  std::vector<glm::vec3> path;
  for (int i = 0; i <= 10; ++i) path.emplace_back(static_cast<float>(i), 0.0F, 0.0F);
  for (int i = 0; i <= 10; ++i) path.emplace_back(10.0F - static_cast<float>(i), 0.0F, 2.0F);
  ScriptedHand hand(path, 500.0);
  HandObservation seen;
  seen.tip_direction = {1, 0, 0};
  seen.tip_bend = {0, 1, 0};
  for (int i = 0; i <= 400; ++i) {  // the tip moves from x = 0 to x = 8 on the way out...
    const float z = std::min(1.1F, 0.01F * static_cast<float>(i));  // ...drifting nearer the way back
    seen.tip_mm = {0.02F * static_cast<float>(i), 0.0F, z};
    (void)hand.step(0.001, seen);
  }
  EXPECT_NEAR(hand.progress_mm(), 8.0, 0.2);
}

}  // namespace
}  // namespace cathbox::session
