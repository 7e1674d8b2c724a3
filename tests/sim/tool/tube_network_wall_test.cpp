#include "tool/tube_network_wall.hpp"

#include <gtest/gtest.h>

namespace cathbox::tool {
namespace {

TEST(TubeNetworkWall, StraightTubeDistanceAndNormal) {
  TubeNetworkWall wall({Tube{{0, 0, 0}, {0, 0, 20}, 1.0, 1.0, 3}});
  WallProbe probe;
  probe.center_mm = {0.6, 0, 10};
  probe.radius_mm = 0.2;
  WallHint hint;
  WallContact c;
  ASSERT_TRUE(wall.probe(probe, hint, c));
  EXPECT_NEAR(c.distance_mm, 0.4, 1e-12);
  EXPECT_NEAR(c.normal.x, 1.0, 1e-12);
  EXPECT_NEAR(c.point_mm.x, 1.0, 1e-12);
  EXPECT_EQ(c.segment, 3);
  probe.center_mm = {0.0, 0, 10};
  probe.range_mm = 0.5;
  EXPECT_FALSE(wall.probe(probe, hint, c));  // 0.8 mm of clearance > range
  EXPECT_NEAR(wall.signed_distance({1.5, 0, 10}), -0.5, 1e-12);
}

TEST(TubeNetworkWall, UnionTakesTheDeepestTube) {
  TubeNetworkWall wall({Tube{{0, 0, 0}, {0, 0, 10}, 1.0, 1.0, 0}, Tube{{0, 0, 10}, {10, 0, 10}, 1.0, 1.0, 1}});
  std::int32_t seg = -1;
  EXPECT_NEAR(wall.signed_distance({0, 0, 5}, &seg), 1.0, 1e-12);
  EXPECT_EQ(seg, 0);
  EXPECT_NEAR(wall.signed_distance({5, 0, 10}, &seg), 1.0, 1e-12);
  EXPECT_EQ(seg, 1);
}

}  // namespace
}  // namespace cathbox::tool
