#include "session/centerline_path.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

namespace cathbox::session {
namespace {

// A trunk along +X splitting at x = 10 into an upper branch and a longer lower one, and a
// separate vessel that touches nothing.
std::vector<PathSegment> y_network() {
  std::vector<PathSegment> s(4);
  s[0].points_mm = {{0, 0, 0}, {5, 0, 0}, {10, 0, 0}};
  s[0].children = {1, 2};
  s[1].points_mm = {{10, 0, 0}, {15, 0, 5}, {20, 0, 10}};
  s[1].parents = {0};
  s[2].points_mm = {{10, 0, 0}, {15, 0, -5}, {20, 0, -10}, {25, 0, -15}};
  s[2].parents = {0};
  s[3].points_mm = {{100, 0, 0}, {110, 0, 0}};
  return s;
}

bool passes(const std::vector<glm::vec3>& path, const glm::vec3& p) {
  for (const glm::vec3& q : path) {
    if (glm::distance(p, q) < 1e-4F) return true;
  }
  return false;
}

TEST(CenterlinePath, DownTheTrunkIntoTheChosenBranch) {
  const auto s = y_network();
  const auto path = CenterlinePath::between(s, {0, 0.0}, {2, 1.0});
  ASSERT_GE(path.size(), 4U);
  EXPECT_EQ(path.front(), glm::vec3(0, 0, 0));
  EXPECT_EQ(path.back(), glm::vec3(25, 0, -15));
  EXPECT_TRUE(passes(path, {10, 0, 0}));
  EXPECT_TRUE(passes(path, {15, 0, -5}));
  EXPECT_FALSE(passes(path, {15, 0, 5}));
  for (std::size_t i = 1; i < path.size(); ++i) EXPECT_GT(glm::distance(path[i], path[i - 1]), 0.0F);
}

TEST(CenterlinePath, BackUpOneBranchAndDownTheOther) {
  const auto s = y_network();
  const auto path = CenterlinePath::between(s, {1, 1.0}, {2, 0.5});
  ASSERT_GE(path.size(), 3U);
  EXPECT_EQ(path.front(), glm::vec3(20, 0, 10));
  EXPECT_TRUE(passes(path, {15, 0, 5}));
  EXPECT_TRUE(passes(path, {10, 0, 0}));
  EXPECT_FALSE(passes(path, {0, 0, 0}));  // the trunk's start is not on the way
  EXPECT_NEAR(glm::distance(path.back(), CenterlinePath::point_at(s[2], 0.5)), 0.0F, 1e-5F);
}

TEST(CenterlinePath, WithinOneSegmentEitherWay) {
  const auto s = y_network();
  const auto fwd = CenterlinePath::between(s, {2, 0.1}, {2, 0.9});
  const auto back = CenterlinePath::between(s, {2, 0.9}, {2, 0.1});
  ASSERT_GE(fwd.size(), 2U);
  EXPECT_EQ(fwd.front(), back.back());
  EXPECT_EQ(fwd.back(), back.front());
}

TEST(CenterlinePath, UnreachableTargetsGiveNoPath) {
  const auto s = y_network();
  EXPECT_TRUE(CenterlinePath::between(s, {0, 0.0}, {3, 1.0}).empty());
  EXPECT_TRUE(CenterlinePath::between(s, {0, 0.0}, {9, 1.0}).empty());
}

TEST(CenterlinePath, NearestPointAndFarthestLeaf) {
  const auto s = y_network();
  const PathPoint n = CenterlinePath::nearest(s, {15.5F, 1.0F, -5.0F});
  EXPECT_EQ(n.segment, 2U);
  EXPECT_GT(n.fraction, 0.2);
  EXPECT_LT(n.fraction, 0.5);
  const auto leaf = CenterlinePath::farthest_leaf(s, {0, 0.0});
  ASSERT_TRUE(leaf);
  EXPECT_EQ(leaf->segment, 2U);  // the longer branch (the disconnected vessel is unreachable)
  EXPECT_DOUBLE_EQ(leaf->fraction, 1.0);
  EXPECT_EQ(CenterlinePath::point_at(s[0], 0.25), glm::vec3(2.5F, 0, 0));
}

}  // namespace
}  // namespace cathbox::session
