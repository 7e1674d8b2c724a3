#include "app/orbit_camera.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

namespace cathbox::app {
namespace {

glm::vec3 to_ndc(const glm::mat4& vp, const glm::vec3& p) {
  const glm::vec4 c = vp * glm::vec4(p, 1.0F);
  return glm::vec3(c) / c.w;
}

TEST(OrbitCamera, FramingKeepsEveryCornerOfTheBoxOnScreen) {
  OrbitCamera cam;
  const glm::vec3 lo{-40.0F, 10.0F, -5.0F};
  const glm::vec3 hi{60.0F, 30.0F, 120.0F};
  cam.frame(lo, hi);
  const glm::mat4 vp = cam.projection(16.0F / 9.0F) * cam.view();
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 corner{(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z};
    const glm::vec3 ndc = to_ndc(vp, corner);
    EXPECT_LE(std::abs(ndc.x), 1.0F) << i;
    EXPECT_LE(std::abs(ndc.y), 1.0F) << i;
    EXPECT_GT(ndc.z, -1.0F) << i;
    EXPECT_LT(ndc.z, 1.0F) << i;
  }
  // The centre projects to the middle, and +Z is up on screen.
  const glm::vec3 c = to_ndc(vp, 0.5F * (lo + hi));
  EXPECT_NEAR(c.x, 0.0F, 1e-5F);
  EXPECT_NEAR(c.y, 0.0F, 1e-5F);
  EXPECT_GT(to_ndc(vp, 0.5F * (lo + hi) + glm::vec3(0, 0, 10)).y, c.y);
}

TEST(OrbitCamera, OrbitKeepsDistanceZoomChangesItPanMovesTheTarget) {
  OrbitCamera cam;
  cam.frame(glm::vec3(-10.0F), glm::vec3(10.0F));
  const float d = cam.distance_mm;
  cam.orbit(120.0F, -40.0F);
  EXPECT_NEAR(glm::distance(cam.eye_mm(), cam.target_mm), d, 1e-3F);
  cam.orbit(0.0F, 1e6F);  // pitch is clamped short of the pole
  EXPECT_LT(cam.pitch_rad, 1.5708F);
  cam.zoom(3.0F);
  EXPECT_NEAR(cam.distance_mm, d * 0.729F, 1e-3F);
  const glm::vec3 before = cam.target_mm;
  const glm::vec3 eye_before = cam.eye_mm();
  cam.pan(100.0F, 0.0F, 720.0F);
  const glm::vec3 moved = cam.target_mm - before;
  EXPECT_GT(glm::length(moved), 0.0F);
  // Panning moves eye and target together, in the view plane.
  EXPECT_NEAR(glm::length((cam.eye_mm() - eye_before) - moved), 0.0F, 1e-3F);
  EXPECT_NEAR(glm::dot(moved, glm::normalize(before - eye_before)), 0.0F, 1e-3F);
}

TEST(EndoCamera, LooksAlongTheTipDirectionFromJustAheadOfTheTip) {
  const glm::vec3 tip{5.0F, 6.0F, 7.0F};
  const glm::vec3 dir{0.0F, 1.0F, 0.0F};
  const glm::mat4 v = EndoCamera::view(tip, dir, glm::vec3(0, 0, 1), 0.5F);
  const glm::vec4 tip_eye = v * glm::vec4(tip, 1.0F);
  EXPECT_NEAR(tip_eye.x, 0.0F, 1e-5F);
  EXPECT_NEAR(tip_eye.y, 0.0F, 1e-5F);
  EXPECT_NEAR(tip_eye.z, 0.5F, 1e-5F);  // the tip is 0.5 mm behind the eye
  const glm::vec4 ahead = v * glm::vec4(tip + 10.0F * dir, 1.0F);
  EXPECT_NEAR(ahead.z, -9.5F, 1e-5F);  // and the way ahead in front of it
  // +Z (the up hint) is up in the view.
  EXPECT_GT((v * glm::vec4(tip + 10.0F * dir + glm::vec3(0, 0, 1), 1.0F)).y, 0.5F);
  // An up hint parallel to the direction still gives a valid view.
  const glm::mat4 w = EndoCamera::view(tip, dir, dir, 0.5F);
  EXPECT_NEAR((w * glm::vec4(tip + 10.0F * dir, 1.0F)).z, -9.5F, 1e-5F);
}

}  // namespace
}  // namespace cathbox::app

namespace cathbox::app {
namespace {

TEST(OrbitCamera, PickingRaysPassThroughWhatThePixelShows) {
  OrbitCamera cam;
  cam.frame(glm::vec3(-20.0F, -5.0F, 0.0F), glm::vec3(30.0F, 5.0F, 80.0F));
  cam.orbit(37.0F, -21.0F);
  const float w = 800.0F;
  const float h = 600.0F;
  const glm::vec3 centre_dir = cam.ray_through(w / 2, h / 2, w, h);
  EXPECT_NEAR(glm::dot(centre_dir, glm::normalize(cam.target_mm - cam.eye_mm())), 1.0F, 1e-5F);
  const glm::mat4 vp = cam.projection(w / h) * cam.view();
  const glm::vec3 p{12.0F, 3.0F, 55.0F};
  const glm::vec3 ndc = to_ndc(vp, p);
  const glm::vec3 dir = cam.ray_through((ndc.x * 0.5F + 0.5F) * w, (0.5F - ndc.y * 0.5F) * h, w, h);
  const glm::vec3 to_p = p - cam.eye_mm();
  const float miss = glm::length(to_p - glm::dot(to_p, dir) * dir);
  EXPECT_LT(miss, 1e-3F);
}

}  // namespace
}  // namespace cathbox::app
