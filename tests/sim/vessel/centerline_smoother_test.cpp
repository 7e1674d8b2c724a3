#include "vessel/centerline_smoother.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "vessel/case_generator.hpp"

namespace cathbox::vessel {
namespace {

TEST(CenterlineSmoother, OnePassFollowsEquationTwoInPlace) {
  // u = 0, 4, 0, 0 (x only): v2 = (0 + 8 + 0)/4 = 2, v3 = (v2 + 0 + 0)/4 = 0.5; ends fixed.
  std::vector<CenterlinePoint> p = {{{0, 0, 0}, 1.0}, {{4, 0, 0}, 3.0}, {{0, 0, 0}, 1.0}, {{0, 0, 0}, 1.0}};
  smooth_polyline(p);
  EXPECT_DOUBLE_EQ(p[0].pos_mm.x, 0.0);
  EXPECT_DOUBLE_EQ(p[1].pos_mm.x, 2.0);
  EXPECT_DOUBLE_EQ(p[2].pos_mm.x, 0.5);
  EXPECT_DOUBLE_EQ(p[3].pos_mm.x, 0.0);
  EXPECT_DOUBLE_EQ(p[1].radius_mm, 2.0);    // (1 + 6 + 1)/4
  EXPECT_DOUBLE_EQ(p[2].radius_mm, 1.25);   // (2 + 2 + 1)/4
}

TEST(CenterlineSmoother, KeepsEvenlySpacedLinesAndLinearRadii) {
  std::vector<CenterlinePoint> p;
  for (int i = 0; i < 10; ++i) p.push_back({{1.0 * i, 2.0 * i, -0.5 * i}, 3.0 - 0.1 * i});
  const std::vector<CenterlinePoint> before = p;
  for (int pass = 0; pass < 3; ++pass) smooth_polyline(p);
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_NEAR(glm::length(p[i].pos_mm - before[i].pos_mm), 0.0, 1e-12);
    EXPECT_NEAR(p[i].radius_mm, before[i].radius_mm, 1e-12);
  }
}

TEST(CenterlineSmoother, FixesEndsAndJunctionPointsAndSnapsJunctions) {
  VesselModel model = CaseGenerator::y_bifurcation();
  model.segments[1].points.front().pos_mm += glm::dvec3(0.3, 0.0, 0.0);  // child starts "near" the parent's end
  const VesselGraph graph(model);
  const VesselModel smoothed = smooth_centerlines(model, graph, 3);
  const glm::dvec3 center = graph.junctions()[0].center_mm;
  EXPECT_EQ(smoothed.segments[0].points.back().pos_mm, center);
  EXPECT_EQ(smoothed.segments[1].points.front().pos_mm, center);
  EXPECT_EQ(smoothed.segments[2].points.front().pos_mm, center);
  EXPECT_EQ(smoothed.segments[0].points.front(), model.segments[0].points.front());
  EXPECT_EQ(smoothed.segments[1].points.back(), model.segments[1].points.back());
  const VesselModel unsnapped = smooth_centerlines(model, graph, 3, false);
  EXPECT_EQ(unsnapped.segments[1].points.front(), model.segments[1].points.front());
}

TEST(CenterlineSmoother, ReducesNoise) {
  std::vector<CenterlinePoint> p;
  for (int i = 0; i < 40; ++i) p.push_back({{1.0 * i, (i % 2 == 0 ? 0.5 : -0.5), 0.0}, 1.0});
  for (int pass = 0; pass < 3; ++pass) smooth_polyline(p);
  for (std::size_t i = 3; i + 3 < p.size(); ++i) EXPECT_LT(std::abs(p[i].pos_mm.y), 0.1) << i;
}

}  // namespace
}  // namespace cathbox::vessel
