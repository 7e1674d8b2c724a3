#include <cmath>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "flow/fluoro_dose.hpp"
#include "flow/head_phantom.hpp"
#include "flow/xray_material.hpp"

namespace cathbox::flow {
namespace {

TEST(XrayMaterial, NistValuesAtFiftyKeV) {
  EXPECT_NEAR(mass_attenuation_cm2_g(XrayMaterial::kIodine), 12.32, 1e-9);
  EXPECT_NEAR(mass_attenuation_cm2_g(XrayMaterial::kCorticalBone), 0.4242, 1e-9);
  EXPECT_NEAR(mass_attenuation_cm2_g(XrayMaterial::kSoftTissue), 0.2223, 1e-9);
  EXPECT_NEAR(mass_attenuation_cm2_g(XrayMaterial::kPlatinum), 6.954, 1e-9);
  // Grid points and interpolation between them.
  EXPECT_NEAR(mass_attenuation_cm2_g(XrayMaterial::kIodine, 40.0), 22.10, 1e-9);
  const double mid = mass_attenuation_cm2_g(XrayMaterial::kIodine, 45.0);
  EXPECT_LT(mid, 22.10);
  EXPECT_GT(mid, 12.32);
  // Linear coefficients: bone 1.92 g/cm^3 -> 0.0814 /mm; 300 mgI/mL of iodine -> 0.37 /mm.
  EXPECT_NEAR(linear_attenuation_per_mm(XrayMaterial::kCorticalBone), 0.4242 * 1.92 * 0.1, 1e-12);
  EXPECT_NEAR(300.0 * iodine_per_mm_per_mgI_ml(), 0.3696, 1e-4);
  // What makes tools visible: platinum >> nitinol > steel-like, all >> tissue.
  EXPECT_GT(linear_attenuation_per_mm(XrayMaterial::kPlatinum), 10.0 * linear_attenuation_per_mm(XrayMaterial::kNitinol));
  EXPECT_GT(linear_attenuation_per_mm(XrayMaterial::kNitinol), 20.0 * linear_attenuation_per_mm(XrayMaterial::kSoftTissue));
  EXPECT_EQ(linear_attenuation_per_mm(XrayMaterial::kAir), 0.0);
}

TEST(HeadPhantom, ChordsOfEachShapeAreExact) {
  const glm::dvec3 o{0, -500, 0}, d{0, 1, 0};
  PhantomShape sphere{"s", ShapeKind::kEllipsoid, {0, 0, 0}, {10, 20, 30}, -1e9, 1e9, 1.0};
  EXPECT_NEAR(HeadPhantom::chord_mm(sphere, o, d), 40.0, 1e-9);
  EXPECT_NEAR(HeadPhantom::chord_mm(sphere, o + glm::dvec3(5, 0, 0), d), 40.0 * std::sqrt(0.75), 1e-9);
  sphere.z_min_mm = 1.0;  // cut: the ray at z 0 misses it
  EXPECT_EQ(HeadPhantom::chord_mm(sphere, o, d), 0.0);
  PhantomShape cyl{"c", ShapeKind::kCylinderZ, {0, 0, 0}, {10, 5, 50}, -1e9, 1e9, 1.0};
  EXPECT_NEAR(HeadPhantom::chord_mm(cyl, o, d), 10.0, 1e-9);
  EXPECT_NEAR(HeadPhantom::chord_mm(cyl, {0, 0, -500}, {0, 0, 1}), 100.0, 1e-9);  // along its axis
  PhantomShape box{"b", ShapeKind::kBox, {0, 0, 0}, {10, 20, 30}, -1e9, 1e9, 1.0};
  const glm::dvec3 diag = glm::normalize(glm::dvec3(0, 1, 1));
  EXPECT_NEAR(HeadPhantom::chord_mm(box, glm::dvec3(0, -100, -100), diag), 40.0 * std::sqrt(2.0), 1e-9);  // y = z in [-20, 20]
  EXPECT_EQ(HeadPhantom::chord_mm(box, {50, -500, 0}, d), 0.0);
}

TEST(HeadPhantom, SkullSpineAndSoftTissueShowWhereTheyAre) {
  const HeadPhantom phantom = HeadPhantom::neuro();
  const double tissue = linear_attenuation_per_mm(XrayMaterial::kSoftTissue);
  const double bone = linear_attenuation_per_mm(XrayMaterial::kCorticalBone);
  // An AP ray through the head's centre above the skull base crosses ~190 mm of head, two 6 mm
  // tables of the skull on the way in and out.
  const glm::dvec3 d{0, 1, 0};
  const double through_brain = phantom.path_mu({0, -500, 260}, d);
  EXPECT_GT(through_brain, 180.0 * tissue);
  EXPECT_LT(through_brain, 200.0 * tissue + 14.0 * (bone - tissue));
  // A lateral ray grazing the skull's side is mostly bone; one beside the head sees nothing.
  EXPECT_GT(phantom.path_mu({-500, 5, 240}, {1, 0, 0}), phantom.path_mu({-500, 5, 330}, {1, 0, 0}));
  EXPECT_EQ(phantom.path_mu({0, -500, 400}, d), 0.0);
  // The cervical spine adds bone to an AP ray through the neck's midline.
  EXPECT_GT(phantom.path_mu({0, -500, 110}, d), phantom.path_mu({-40, -500, 110}, d) + 10.0 * (bone - tissue));
  // The airway subtracts.
  EXPECT_LT(phantom.path_mu({0, 22, -500}, {0, 0, 1}), phantom.path_mu({8, 0, -500}, {0, 0, 1}));
}

TEST(HeadPhantom, ProjectionMatchesRayByRayAndCoversTheField) {
  const HeadPhantom phantom = HeadPhantom::neuro();
  CArmPose p;
  p.lao_deg = 30.0;
  const CArm c(p);
  const int w = 96, h = 80;
  const std::vector<float> img = phantom.project(c, w, h);
  ASSERT_EQ(img.size(), static_cast<std::size_t>(w * h));
  for (int y = 0; y < h; y += 7) {
    for (int x = 0; x < w; x += 5) {
      const double direct = phantom.path_mu(c.source_mm(), c.pixel_ray(x + 0.5, y + 0.5, w, h));
      ASSERT_NEAR(img[static_cast<std::size_t>(y * w + x)], direct, 1e-4 * (1.0 + direct)) << x << "," << y;
    }
  }
  const double t = phantom.central_transmission(c);
  EXPECT_GT(t, 1e-3);  // a head transmits ~1 % at 50 keV
  EXPECT_LT(t, 0.05);
}

TEST(FluoroDose, DapQuantaAndNoise) {
  const FluoroDose dose;
  // DAP = K_det * A / (T * T_grid): 40 nGy, 484 cm^2, 1 % transmission, grid 0.7.
  EXPECT_NEAR(dose.dap_per_pulse_Gy_cm2(ExposureMode::kFluoroscopy, 484.0, 0.01), 40e-9 * 484.0 / (0.01 * 0.7), 1e-15);
  EXPECT_NEAR(dose.dap_per_pulse_Gy_cm2(ExposureMode::kSubtractionRun, 484.0, 0.01),
              25.0 * dose.dap_per_pulse_Gy_cm2(ExposureMode::kFluoroscopy, 484.0, 0.01), 1e-12);
  // Fluence per kerma at 50 keV: 1 / (E mu_en/rho) = 30.5 photons / mm^2 / nGy.
  EXPECT_NEAR(dose.photons_per_mm2_per_nGy(), 30.46, 0.05);
  // Entrance kerma: inverse square from the detector plane.
  EXPECT_NEAR(dose.entrance_kerma_mGy(ExposureMode::kFluoroscopy, 0.01, 1000.0, 500.0),
              4.0 * dose.entrance_kerma_mGy(ExposureMode::kFluoroscopy, 0.01, 1000.0, 1000.0), 1e-12);
  // Noise: a subtraction frame (25x the quanta, no temporal filter) is less noisy per frame.
  const double px = 220.0 / 1024.0;
  const double n = dose.quanta_per_pixel(ExposureMode::kFluoroscopy, px);
  EXPECT_NEAR(n, 40.0 * dose.photons_per_mm2_per_nGy() * px * px * 0.65, 1e-9);
  EXPECT_NEAR(dose.log_noise_sigma(ExposureMode::kSubtractionRun, px), 1.0 / std::sqrt(25.0 * n), 1e-12);
  EXPECT_NEAR(dose.log_noise_sigma(ExposureMode::kFluoroscopy, px), std::sqrt(0.25 / 1.75) / std::sqrt(n), 1e-12);
}

}  // namespace
}  // namespace cathbox::flow
