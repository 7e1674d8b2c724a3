#include "flow/c_arm.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "lumen.hpp"

namespace cathbox::flow {

std::vector<NamedProjection> standard_projections() {
  return {{"AP", 0.0, 0.0}, {"lateral", 90.0, 0.0}, {"AP cranial 20", 0.0, 20.0}, {"LAO 30", 30.0, 0.0}, {"RAO 30", -30.0, 0.0}};
}

std::string check_pose(const CArmPose& p) {
  const auto in = [](double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; };
  if (!in(p.lao_deg, -120.0, 120.0)) return "C-arm: LAO/RAO angle must be within +-120 degrees";
  if (!in(p.cranial_deg, -60.0, 60.0)) return "C-arm: cranial/caudal angle must be within +-60 degrees";
  if (!in(p.sid_mm, 800.0, 1300.0)) return "C-arm: source to image distance must be in [800, 1300] mm";
  if (!in(p.sod_mm, 400.0, p.sid_mm - 100.0)) return "C-arm: source to isocentre must be in [400, SID - 100] mm";
  if (!in(p.table_height_mm, -200.0, 200.0)) return "C-arm: table height must be within +-200 mm";
  if (!in(p.fov_mm, 100.0, 420.0)) return "C-arm: field of view must be in [100, 420] mm";
  if (!(p.collimation > 0.1 && p.collimation <= 1.0)) return "C-arm: collimation must be in (0.1, 1]";
  if (!std::isfinite(p.isocenter_mm.x) || !std::isfinite(p.isocenter_mm.y) || !std::isfinite(p.isocenter_mm.z)) {
    return "C-arm: isocentre must be finite";
  }
  return {};
}

CArm::CArm(const CArmPose& pose) : pose_(pose) {
  const double l = pose.lao_deg * std::numbers::pi / 180.0;
  const double c = pose.cranial_deg * std::numbers::pi / 180.0;
  beam_ = {std::cos(c) * std::sin(l), std::cos(c) * std::cos(l), std::sin(c)};
  const glm::dvec3 superior{0.0, 0.0, 1.0};
  up_ = glm::normalize(superior - glm::dot(superior, beam_) * beam_);
  right_ = glm::cross(beam_, up_);
  iso_ = pose.isocenter_mm - pose.table_height_mm * glm::dvec3(0.0, 1.0, 0.0);
  source_ = iso_ - pose.sod_mm * beam_;
}

double CArm::depth_mm(const glm::dvec3& p) const { return glm::dot(p - source_, beam_); }

glm::dvec2 CArm::project_mm(const glm::dvec3& p) const {
  const glm::dvec3 d = p - source_;
  const double scale = pose_.sid_mm / glm::dot(d, beam_);
  return {scale * glm::dot(d, right_), scale * glm::dot(d, up_)};
}

double CArm::pixel_mm(int width, int height) const { return pose_.fov_mm / std::min(width, height); }

glm::dvec2 CArm::project_px(const glm::dvec3& p, int width, int height) const {
  const glm::dvec2 mm = project_mm(p);
  const double px = pixel_mm(width, height);
  return {0.5 * width + mm.x / px, 0.5 * height - mm.y / px};
}

glm::dvec3 CArm::pixel_ray(double px, double py, int width, int height) const {
  const double mm = pixel_mm(width, height);
  const glm::dvec3 on_detector =
      detector_center_mm() + (px - 0.5 * width) * mm * right_ - (py - 0.5 * height) * mm * up_;
  return glm::normalize(on_detector - source_);
}

glm::mat4 CArm::view_matrix() const {
  return glm::mat4(glm::lookAt(source_, source_ + beam_, up_));
}

glm::mat4 CArm::projection_matrix(int width, int height, double near_mm, double far_mm) const {
  // The detector half-extents scaled back to the near plane.
  const double mm = pixel_mm(width, height);
  const double half_w = 0.5 * width * mm * near_mm / pose_.sid_mm;
  const double half_h = 0.5 * height * mm * near_mm / pose_.sid_mm;
  return glm::mat4(glm::frustum(-half_w, half_w, -half_h, half_h, near_mm, far_mm));
}

double CArm::field_area_cm2() const {
  const double side_cm = 0.1 * pose_.fov_mm * pose_.collimation;
  return side_cm * side_cm;
}

bool CArm::in_field(const glm::dvec2& d) const {
  const double half = 0.5 * pose_.fov_mm * pose_.collimation;
  return std::abs(d.x) <= half && std::abs(d.y) <= half;
}

}  // namespace cathbox::flow
