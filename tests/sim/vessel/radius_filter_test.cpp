#include "vessel/radius_filter.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "vessel/case_generator.hpp"

namespace cathbox::vessel {
namespace {

VesselModel one_segment(const std::vector<double>& radii) {
  VesselModel model;
  Segment s;
  s.id = 1;
  for (std::size_t i = 0; i < radii.size(); ++i) s.points.push_back({{0.0, 0.0, 0.5 * static_cast<double>(i)}, radii[i]});
  model.segments.push_back(std::move(s));
  return model;
}

std::vector<double> radii_of(const VesselModel& model) {
  std::vector<double> out;
  for (const CenterlinePoint& p : model.segments[0].points) out.push_back(p.radius_mm);
  return out;
}

TEST(RadiusFilter, LeavesTheBundledAndGeneratedCasesAsTheyAre) {
  for (const std::string& name : CaseGenerator::case_names()) {
    VesselModel model = CaseGenerator::make_case(name);
    const VesselModel before = model;
    const RadiusFilterReport report = filter_radii(model);
    EXPECT_EQ(report.changed, 0u) << name;
    EXPECT_EQ(model, before) << name;
    EXPECT_EQ(report.summary(), "changed no radius");
  }
}

TEST(RadiusFilter, ReplacesSpikesDropsAndShortRunsButKeepsNoise) {
  // Measured radii: 2 mm with +-2 % noise, a spike (+60 %), a two-point drop (-50 %), a zero and
  // a NaN where the measurement failed.
  std::vector<double> r(40);
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = 2.0 * (1.0 + 0.02 * std::sin(1.7 * static_cast<double>(i)));
  const std::vector<double> clean = r;
  r[8] = 3.2;
  r[20] = r[21] = 1.0;
  r[30] = 0.0;
  r[35] = std::numeric_limits<double>::quiet_NaN();
  VesselModel model = one_segment(r);
  const RadiusFilterReport report = filter_radii(model);
  const std::vector<double> got = radii_of(model);
  EXPECT_EQ(report.changed, 5u);
  EXPECT_EQ(report.segments_changed, 1u);
  EXPECT_NEAR(report.max_relative_change, 1.0, 1e-12);  // the zero and the NaN count as 100 %
  for (std::size_t i : {8u, 20u, 21u, 30u, 35u}) EXPECT_NEAR(got[i], 2.0, 0.04) << i;  // within the noise
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (i == 8 || i == 20 || i == 21 || i == 30 || i == 35) continue;
    EXPECT_EQ(got[i], clean[i]) << i;  // the noise is left as it is
  }
  EXPECT_EQ(report.summary(), "changed 5 of 40 radii in 1 segments (max 100 %)");
}

TEST(RadiusFilter, KeepsStenosesBulgesAndStepsOfThreePointsOrMore) {
  std::vector<double> r(40, 2.0);
  for (std::size_t i = 10; i < 13; ++i) r[i] = 0.6;   // a 70 % stenosis three points long
  for (std::size_t i = 20; i < 24; ++i) r[i] = 3.0;   // a bulge
  for (std::size_t i = 30; i < 40; ++i) r[i] = 1.4;   // a step (a smaller branch continues)
  VesselModel model = one_segment(r);
  const RadiusFilterReport report = filter_radii(model);
  EXPECT_EQ(report.changed, 0u);
  EXPECT_EQ(radii_of(model), r);
}

TEST(RadiusFilter, EndsAndShortSegments) {
  // An outlet whose last point collapsed (VMTK's sphere shrinks at the cap) and a two-point segment.
  VesselModel model = one_segment({1.5, 1.52, 1.49, 1.51, 1.5, 1.48, 0.2});
  EXPECT_EQ(filter_radii(model).changed, 1u);
  EXPECT_NEAR(radii_of(model).back(), 1.5, 0.02);
  VesselModel two = one_segment({1.0, 3.0});
  EXPECT_EQ(filter_radii(two).changed, 0u);
  VesselModel none = one_segment({0.0, -1.0, 0.0});
  const RadiusFilterReport unusable = filter_radii(none);
  EXPECT_EQ(unusable.unusable_segments, 1u);
  EXPECT_EQ(unusable.changed, 0u);
}

}  // namespace
}  // namespace cathbox::vessel
