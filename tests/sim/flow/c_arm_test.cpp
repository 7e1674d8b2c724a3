#include "flow/c_arm.hpp"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

namespace cathbox::flow {
namespace {

void expect_near(const glm::dvec2& a, const glm::dvec2& b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
}

TEST(CArm, IsocentreProjectsToTheImageCentreAtEveryAngle) {
  for (double lao : {-90.0, -30.0, 0.0, 45.0, 90.0}) {
    for (double cran : {-30.0, 0.0, 25.0}) {
      CArmPose p;
      p.lao_deg = lao;
      p.cranial_deg = cran;
      const CArm c(p);
      expect_near(c.project_px(p.isocenter_mm, 1024, 768), {512.0, 384.0}, 1e-9);
      EXPECT_NEAR(glm::length(c.beam_direction()), 1.0, 1e-12);
      EXPECT_NEAR(glm::dot(c.beam_direction(), c.image_up()), 0.0, 1e-12);
      EXPECT_NEAR(glm::dot(c.image_right(), c.image_up()), 0.0, 1e-12);
      EXPECT_NEAR(c.magnification(p.isocenter_mm), p.sid_mm / p.sod_mm, 1e-12);
      EXPECT_NEAR(glm::length(c.source_mm() - p.isocenter_mm), p.sod_mm, 1e-9);
    }
  }
}

TEST(CArm, ApAndLateralShowThePatientTheUsualWay) {
  CArmPose p;
  const CArm ap(p);
  const glm::dvec3 iso = p.isocenter_mm;
  // AP: the beam runs posterior to anterior; the patient's left is on the image right, up is superior.
  EXPECT_NEAR(ap.beam_direction().y, 1.0, 1e-12);
  EXPECT_GT(ap.project_px(iso + glm::dvec3(10, 0, 0), 1000, 1000).x, 500.0);
  EXPECT_LT(ap.project_px(iso + glm::dvec3(0, 0, 10), 1000, 1000).y, 500.0);
  // A displacement along the beam only changes the magnification.
  expect_near(ap.project_mm(iso + glm::dvec3(0, 40, 0)), {0.0, 0.0}, 1e-9);
  EXPECT_NEAR(ap.magnification(iso + glm::dvec3(0, 40, 0)), p.sid_mm / (p.sod_mm + 40.0), 1e-12);
  // Lateral (LAO 90): the beam runs right to left, anterior is on the image left.
  p.lao_deg = 90.0;
  const CArm lat(p);
  EXPECT_NEAR(lat.beam_direction().x, 1.0, 1e-12);
  EXPECT_LT(lat.project_px(iso + glm::dvec3(0, 10, 0), 1000, 1000).x, 500.0);
  expect_near(lat.project_mm(iso + glm::dvec3(25, 0, 0)), {0.0, 0.0}, 1e-9);
  // Magnification: a point 10 mm right of the isocentre in AP lands 10 * SID/SOD mm right.
  expect_near(ap.project_mm(iso + glm::dvec3(10, 0, 0)), {10.0 * p.sid_mm / p.sod_mm, 0.0}, 1e-9);
}

TEST(CArm, RotationMovesTheProjectionAsTheGeometryPredicts) {
  // A point 30 mm to the patient's left of the isocentre: in a LAO l view it lies at depth
  // 30 sin(l) from the isocentre and 30 cos(l) to the image right.
  CArmPose p;
  const glm::dvec3 q = p.isocenter_mm + glm::dvec3(30, 0, 0);
  for (double lao : {-60.0, -20.0, 0.0, 20.0, 60.0}) {
    p.lao_deg = lao;
    const CArm c(p);
    const double l = lao * 3.14159265358979323846 / 180.0;
    const double depth = p.sod_mm + 30.0 * std::sin(l);
    EXPECT_NEAR(c.project_mm(q).x, 30.0 * std::cos(l) * p.sid_mm / depth, 1e-9) << lao;
    EXPECT_NEAR(c.project_mm(q).y, 0.0, 1e-9);
  }
  // Cranial tilt: a point above the isocentre moves down the image by cos(c).
  p.lao_deg = 0.0;
  const glm::dvec3 up = p.isocenter_mm + glm::dvec3(0, 0, 40);
  for (double cran : {-30.0, 15.0, 30.0}) {
    p.cranial_deg = cran;
    const CArm c(p);
    const double a = cran * 3.14159265358979323846 / 180.0;
    EXPECT_NEAR(c.project_mm(up).y, 40.0 * std::cos(a) * p.sid_mm / (p.sod_mm + 40.0 * std::sin(a)), 1e-9) << cran;
  }
}

TEST(CArm, TableHeightChangesMagnification) {
  CArmPose p;
  p.table_height_mm = 50.0;  // the patient moves 50 mm towards the AP detector
  const CArm c(p);
  EXPECT_NEAR(c.magnification(p.isocenter_mm), p.sid_mm / (p.sod_mm + 50.0), 1e-12);
  EXPECT_NEAR(c.isocenter_mm().y, p.isocenter_mm.y - 50.0, 1e-12);
}

TEST(CArm, GlMatricesAgreeWithTheProjection) {
  for (double lao : {-35.0, 0.0, 70.0}) {
    CArmPose p;
    p.lao_deg = lao;
    p.cranial_deg = 12.0;
    const CArm c(p);
    const int w = 1024, h = 640;
    const glm::dmat4 m = glm::dmat4(c.projection_matrix(w, h, 100.0, 2000.0)) * glm::dmat4(c.view_matrix());
    for (const glm::dvec3& q : {glm::dvec3(10, 20, 200), glm::dvec3(-40, -5, 250), glm::dvec3(0, 10, 225)}) {
      const glm::dvec4 clip = m * glm::dvec4(q, 1.0);
      const glm::dvec2 px{(clip.x / clip.w * 0.5 + 0.5) * w, (0.5 - clip.y / clip.w * 0.5) * h};
      expect_near(px, c.project_px(q, w, h), 1e-2);
    }
  }
}

TEST(CArm, PixelRaysPassThroughTheirPixels) {
  CArmPose p;
  p.lao_deg = 25.0;
  const CArm c(p);
  const glm::dvec3 ray = c.pixel_ray(300.5, 700.5, 1024, 1024);
  const glm::dvec3 point = c.source_mm() + 800.0 * ray;
  expect_near(c.project_px(point, 1024, 1024), {300.5, 700.5}, 1e-6);
}

TEST(CArm, FieldAndPoseChecks) {
  CArmPose p;
  p.fov_mm = 200.0;
  p.collimation = 0.5;
  const CArm c(p);
  EXPECT_NEAR(c.field_area_cm2(), 100.0, 1e-9);
  EXPECT_TRUE(c.in_field({49.0, -49.0}));
  EXPECT_FALSE(c.in_field({51.0, 0.0}));
  EXPECT_EQ(check_pose(p), "");
  p.lao_deg = 150.0;
  EXPECT_EQ(check_pose(p), "C-arm: LAO/RAO angle must be within +-120 degrees");
  p = {};
  p.sid_mm = 2000.0;
  EXPECT_NE(check_pose(p), "");
  EXPECT_GE(standard_projections().size(), 2u);
  EXPECT_EQ(standard_projections()[1].lao_deg, 90.0);
}

}  // namespace
}  // namespace cathbox::flow
