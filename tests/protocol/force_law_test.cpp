// The local force law and the output curve, as the firmware renders them.
#include <gtest/gtest.h>

#include <climits>

#include "protocol/cbx_command_report.h"
#include "protocol/cbx_feature_reports.h"

TEST(ForceLaw, SpringDamperAndClamp) {
  // A wall at 250 mm, 400 N/m (= 400000 mN/m), 2 N*s/m damping, clamped to [-3000, 0] mN.
  const cbx_force_law law{-200, 250000, 400000, 2000, -3000, 0};
  EXPECT_EQ(cbx_force_law_eval(&law, 250000, 0), -200);
  // 1 mm into the wall: -200 - 400000 * 1000 / 1e6 = -600 (pushes back out).
  EXPECT_EQ(cbx_force_law_eval(&law, 251000, 0), -600);
  // 10 mm in, moving further in at 10 mm/s: -200 - 4000 - 20 -> clamped to -3000.
  EXPECT_EQ(cbx_force_law_eval(&law, 260000, 10000), -3000);
  // 1 mm before the wall, moving out at 10 mm/s: -200 + 400 + 20 = +220 -> clamped to 0.
  EXPECT_EQ(cbx_force_law_eval(&law, 249000, -10000), 0);
  // 0.5 mm in, moving out at 10 mm/s: -200 - 200 + 20 = -380 (the damper eases the push).
  EXPECT_EQ(cbx_force_law_eval(&law, 250500, -10000), -380);
  EXPECT_EQ(cbx_force_law_eval(&law, -2000000000, 0), 0);
}

TEST(ForceLaw, NoOverflowAtExtremes) {
  const cbx_force_law law{INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MIN, INT32_MAX};
  EXPECT_EQ(cbx_force_law_eval(&law, INT32_MIN, INT32_MIN), INT32_MAX);
  const cbx_force_law negative{INT32_MIN, INT32_MIN, INT32_MAX, INT32_MAX, INT32_MIN, INT32_MAX};
  EXPECT_EQ(cbx_force_law_eval(&negative, INT32_MAX, INT32_MAX), INT32_MIN);
}

TEST(ForceLaw, RangeCheck) {
  cbx_force_law law{0, 0, 0, 0, 0, 0};
  EXPECT_EQ(cbx_force_law_check(&law), CBX_OK);
  law.out_min = 1;
  EXPECT_EQ(cbx_force_law_check(&law), CBX_ERR_RANGE);
  law = {0, 0, -1, 0, 0, 0};
  EXPECT_EQ(cbx_force_law_check(&law), CBX_ERR_RANGE);
  law = {0, 0, 0, -1, 0, 0};
  EXPECT_EQ(cbx_force_law_check(&law), CBX_ERR_RANGE);
}

TEST(OutputCurve, InterpolatesThroughOriginAndPointsThenHolds) {
  const cbx_curve_point curve[CBX_CURVE_POINTS] = {{100, 180}, {300, 390}, {600, 650}, {900, 950}};
  EXPECT_EQ(cbx_curve_apply(curve, 0), 0);
  EXPECT_EQ(cbx_curve_apply(curve, 50), 90);
  EXPECT_EQ(cbx_curve_apply(curve, 100), 180);
  EXPECT_EQ(cbx_curve_apply(curve, 200), 285);
  EXPECT_EQ(cbx_curve_apply(curve, 900), 950);
  EXPECT_EQ(cbx_curve_apply(curve, 1000), 950);
}
