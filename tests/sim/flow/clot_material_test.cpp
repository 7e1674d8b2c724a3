// The clot's material against the published measurements it is built from.
#include <gtest/gtest.h>

#include <string>

#include "flow/clot_material.hpp"

namespace cathbox::flow {
namespace {

// An unconfined compression test as in the paper: a cylinder between plates, displacement
// steps, force read from the law; the tangent modulus at 75 % strain is taken from the
// force-displacement curve by central differences, as the paper takes it from its curves.
double measured_et75_kPa(const ClotComposition& c) {
  const ClotCompressionLaw law(c);
  const double diameter_mm = 3.0, height_mm = 5.0;
  const double area_mm2 = 3.14159265358979 * 0.25 * diameter_mm * diameter_mm;
  const double dx_mm = 0.005;
  const double x_mm = 0.75 * height_mm;
  const double df_N = law.force_N((x_mm + dx_mm) / height_mm, area_mm2) - law.force_N((x_mm - dx_mm) / height_mm, area_mm2);
  const double stress_kPa = df_N / (area_mm2 * 1e-6) * 1e-3;
  return stress_kPa / (2.0 * dx_mm / height_mm);
}

// Boodt et al., Stroke 2021 (41 thrombi from thrombectomy, unconfined compression): median
// Et75 560 kPa (IQR 393-1161); per % fibrin/platelets +9 kPa (95 % CI 5-13), per % red cells
// -9 kPa (95 % CI -5 to -13).
TEST(ClotMaterial, CompressionStiffnessIsInTheBandOfItsComposition) {
  EXPECT_NEAR(measured_et75_kPa(kReferenceComposition), 560.0, 0.01 * 560.0);
  EXPECT_GT(measured_et75_kPa(kReferenceComposition), 393.0);
  EXPECT_LT(measured_et75_kPa(kReferenceComposition), 1161.0);
  for (double fibrin = 20.0; fibrin <= 70.0; fibrin += 10.0) {
    const ClotComposition c{90.0 - fibrin, fibrin};
    const double d_fibrin = fibrin - 45.0;
    const double d_red = c.red_cell_percent - 45.0;
    // The band of this composition: each slope anywhere in its confidence interval.
    const double a = 560.0 + 5.0 * d_fibrin - 5.0 * d_red;
    const double b = 560.0 + 13.0 * d_fibrin - 13.0 * d_red;
    const double lo = std::min(a, b), hi = std::max(a, b);
    const double e = measured_et75_kPa(c);
    EXPECT_GE(e, lo - 1.0) << "fibrin " << fibrin;
    EXPECT_LE(e, hi + 1.0) << "fibrin " << fibrin;
  }
  // Fibrin-rich stiffer than red-cell-rich.
  EXPECT_GT(measured_et75_kPa({20.0, 70.0}), 3.0 * measured_et75_kPa({60.0, 30.0}));
}

// Cahalane et al., Ann Biomed Eng 2023: clot analogues stiffen strongly in compression; the
// high-strain compressive stiffness is ~40 x the tensile stiffness, which is ~15 x the
// low-strain compressive stiffness (ratio ~600 between the ends of the curve).
TEST(ClotMaterial, CompressionStiffensWithStrain) {
  const ClotCompressionLaw law(kReferenceComposition);
  EXPECT_DOUBLE_EQ(law.stress_kPa(0.0), 0.0);
  double last = -1.0;
  for (double e = 0.0; e <= 0.9; e += 0.05) {
    EXPECT_GT(law.tangent_kPa(e), last);
    last = law.tangent_kPa(e);
  }
  const double ratio = law.tangent_kPa(0.75) / law.tangent_kPa(0.0);
  EXPECT_GT(ratio, 0.5 * 600.0);
  EXPECT_LT(ratio, 2.0 * 600.0);
  // Strains past 95 % are clamped (a clot is not compressed to nothing).
  EXPECT_DOUBLE_EQ(law.stress_kPa(2.0), law.stress_kPa(0.95));
  EXPECT_DOUBLE_EQ(law.stress_kPa(-1.0), 0.0);
  // The linear model never goes negative: a nearly pure red-cell clot floors at 10 % of the median.
  EXPECT_NEAR(clot_et75_kPa({95.0, 5.0}), 56.0, 1e-9);
}

// Elkhayyat et al., J Biomech 2024: clot analogue on arterial wall, static friction 1.49 /
// 0.57 / 0.46 at 0 / 20 / 40 % haematocrit, kinetic 0.26 / 0.23 at 20 / 40 %; fibrin-rich
// clots 3-4 x the friction of red-cell-rich ones.
TEST(ClotMaterial, WallFrictionFollowsTheHaematocritOfTheAnalogue) {
  const ClotFriction fibrin = clot_wall_friction({0.0, 95.0});
  const ClotFriction mixed = clot_wall_friction({45.0, 45.0});
  const ClotFriction red = clot_wall_friction({80.0, 15.0});
  EXPECT_NEAR(fibrin.static_coefficient, 1.49, 1e-12);
  EXPECT_NEAR(mixed.static_coefficient, 0.57, 1e-12);
  EXPECT_NEAR(red.static_coefficient, 0.46, 1e-12);
  EXPECT_NEAR(mixed.kinetic_coefficient, 0.26, 1e-12);
  EXPECT_NEAR(red.kinetic_coefficient, 0.23, 1e-12);
  const double ratio = fibrin.static_coefficient / red.static_coefficient;
  EXPECT_GE(ratio, 3.0);
  EXPECT_LE(ratio, 4.0);
  for (const ClotFriction& f : {fibrin, mixed, red}) EXPECT_LT(f.kinetic_coefficient, f.static_coefficient);
  // Between the measured points: monotone in red cells.
  EXPECT_LT(clot_wall_friction({60.0, 30.0}).static_coefficient, mixed.static_coefficient);
  EXPECT_GT(clot_wall_friction({60.0, 30.0}).static_coefficient, red.static_coefficient);
}

TEST(ClotMaterial, RejectsImpossibleCompositions) {
  EXPECT_STREQ(check_composition({45.0, 45.0}), "");
  EXPECT_STRNE(check_composition({-1.0, 45.0}), "");
  EXPECT_STRNE(check_composition({45.0, 101.0}), "");
  EXPECT_STRNE(check_composition({60.0, 60.0}), "");
  EXPECT_STRNE(check_composition({std::stod("nan"), 10.0}), "");
}

}  // namespace
}  // namespace cathbox::flow
