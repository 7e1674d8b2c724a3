#include "app/orbit_camera.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>
#include <glm/vec4.hpp>

namespace cathbox::app {
namespace {
constexpr float kMaxPitch = 1.55F;
const glm::vec3 kUp{0.0F, 0.0F, 1.0F};
}  // namespace

void OrbitCamera::frame(const glm::vec3& min_mm, const glm::vec3& max_mm) {
  target_mm = 0.5F * (min_mm + max_mm);
  scene_radius_mm = std::max(1.0F, 0.5F * glm::length(max_mm - min_mm));
  distance_mm = scene_radius_mm / std::sin(0.5F * fov_y_rad);
  yaw_rad = -1.5707963F;
  pitch_rad = 0.0F;
}

void OrbitCamera::orbit(float dx_px, float dy_px) {
  yaw_rad -= dx_px * 0.01F;
  pitch_rad = std::clamp(pitch_rad + dy_px * 0.01F, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::zoom(float steps) {
  distance_mm = std::clamp(distance_mm * std::pow(0.9F, steps), 0.5F, 50.0F * scene_radius_mm);
}

void OrbitCamera::pan(float dx_px, float dy_px, float viewport_height_px) {
  const float per_px =
      2.0F * distance_mm * std::tan(0.5F * fov_y_rad) / std::max(1.0F, viewport_height_px);
  const glm::vec3 forward = glm::normalize(target_mm - eye_mm());
  const glm::vec3 right = glm::normalize(glm::cross(forward, kUp));
  const glm::vec3 up = glm::cross(right, forward);
  target_mm += (-dx_px * right + dy_px * up) * per_px;
}

glm::vec3 OrbitCamera::eye_mm() const {
  const glm::vec3 dir{std::cos(pitch_rad) * std::cos(yaw_rad),
                      std::cos(pitch_rad) * std::sin(yaw_rad), std::sin(pitch_rad)};
  return target_mm + distance_mm * dir;
}

glm::mat4 OrbitCamera::view() const { return glm::lookAt(eye_mm(), target_mm, kUp); }

glm::mat4 OrbitCamera::projection(float aspect) const {
  const float near_mm = std::max(0.1F, distance_mm - 2.0F * scene_radius_mm);
  const float far_mm = distance_mm + 2.0F * scene_radius_mm;
  return glm::perspective(fov_y_rad, std::max(1e-3F, aspect), near_mm, far_mm);
}

glm::vec3 OrbitCamera::ray_through(float x_px, float y_px, float width_px, float height_px) const {
  const float ndc_x = 2.0F * x_px / std::max(1.0F, width_px) - 1.0F;
  const float ndc_y = 1.0F - 2.0F * y_px / std::max(1.0F, height_px);
  const glm::mat4 inv = glm::inverse(projection(width_px / std::max(1.0F, height_px)) * view());
  const glm::vec4 near_p = inv * glm::vec4(ndc_x, ndc_y, -1.0F, 1.0F);
  const glm::vec4 far_p = inv * glm::vec4(ndc_x, ndc_y, 1.0F, 1.0F);
  return glm::normalize(glm::vec3(far_p) / far_p.w - glm::vec3(near_p) / near_p.w);
}

glm::mat4 EndoCamera::view(const glm::vec3& tip_mm, const glm::vec3& direction,
                           const glm::vec3& up_hint, float ahead_mm) {
  glm::vec3 dir = glm::length(direction) > 1e-6F ? glm::normalize(direction) : glm::vec3(1, 0, 0);
  glm::vec3 up = up_hint - glm::dot(up_hint, dir) * dir;
  if (glm::length(up) < 1e-4F) {
    up = std::abs(dir.z) < 0.9F ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
    up = up - glm::dot(up, dir) * dir;
  }
  const glm::vec3 eye = tip_mm + ahead_mm * dir;
  return glm::lookAt(eye, eye + dir, glm::normalize(up));
}

glm::mat4 EndoCamera::projection(float aspect) {
  return glm::perspective(1.4F, std::max(1e-3F, aspect), 0.05F, 120.0F);
}

}  // namespace cathbox::app
