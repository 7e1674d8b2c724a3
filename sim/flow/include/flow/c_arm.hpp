#pragma once
// The C-arm of an angiography suite: where the focal spot and the detector are for a pose, and
// where a point of the patient lands on the image. Patient coordinates as the bundled cases:
// x towards the patient's left, y anterior, z superior (the patient lies supine, so y is up).
//
// - Angles: LAO (+) / RAO (-) rotates the detector about the patient's long axis towards the
//   patient's left (right); cranial (+) / caudal (-) tilts it towards the head (feet). At 0/0 the
//   beam runs posterior to anterior (source under the table, detector above: the usual "AP").
//   Beam direction b = (cos c sin l, cos c cos l, sin c) for LAO l and cranial c.
// - Distances: the source is SOD (source to isocentre, fixed by the C-arm) behind the
//   isocentre along b, the detector SID (source to image) from the source. Magnification of a
//   point = SID / (its depth from the source along b): SID/SOD at the isocentre.
// - Table height moves the patient along y (anterior = up): the patient point at the isocentre is
//   `isocenter_mm - table_height_mm * y`; raising the table brings the patient towards an AP
//   detector and lowers the magnification.
// - The image: the detector's field of view (square, fov_mm wide) and a square collimator that
//   opens `collimation` of it. Image up is the patient's superior direction projected on the
//   detector; image right is b x up (patient's left in AP, posterior in a left lateral).
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace cathbox::flow {

struct CArmPose {
  double lao_deg = 0.0;          // + LAO, - RAO, within [-120, 120]
  double cranial_deg = 0.0;      // + cranial, - caudal, within [-60, 60]
  double sid_mm = 1000.0;        // source to image distance, [800, 1300]
  double sod_mm = 750.0;         // source to isocentre, fixed by the gantry
  double table_height_mm = 0.0;  // + raises the patient (towards an AP detector), [-200, 200]
  glm::dvec3 isocenter_mm{0.0, 10.0, 225.0};  // patient point at the isocentre at table height 0
  double fov_mm = 220.0;         // detector field of view (zoom format), [100, 420]
  double collimation = 1.0;      // open fraction of the field of view, (0.1, 1]
  friend bool operator==(const CArmPose&, const CArmPose&) = default;
};

struct NamedProjection {
  std::string name;
  double lao_deg = 0.0;
  double cranial_deg = 0.0;
};

// AP, lateral (LAO 90), AP cranial 20 (Towne-like), LAO 30 and RAO 30 oblique.
[[nodiscard]] std::vector<NamedProjection> standard_projections();
// Empty when the pose is usable; else one line naming the first value out of range.
[[nodiscard]] std::string check_pose(const CArmPose& pose);

class CArm {
 public:
  explicit CArm(const CArmPose& pose = {});

  [[nodiscard]] const CArmPose& pose() const { return pose_; }
  [[nodiscard]] glm::dvec3 beam_direction() const { return beam_; }   // source to detector, unit
  [[nodiscard]] glm::dvec3 image_up() const { return up_; }
  [[nodiscard]] glm::dvec3 image_right() const { return right_; }
  [[nodiscard]] glm::dvec3 isocenter_mm() const { return iso_; }     // with the table height applied
  [[nodiscard]] glm::dvec3 source_mm() const { return source_; }
  [[nodiscard]] glm::dvec3 detector_center_mm() const { return source_ + pose_.sid_mm * beam_; }

  // Depth of a point from the source along the beam, and its magnification SID / depth.
  [[nodiscard]] double depth_mm(const glm::dvec3& p) const;
  [[nodiscard]] double magnification(const glm::dvec3& p) const { return pose_.sid_mm / depth_mm(p); }
  // Where the ray from the source through p meets the detector, in mm from the detector centre
  // (x right, y up). p must be in front of the source (depth > 0).
  [[nodiscard]] glm::dvec2 project_mm(const glm::dvec3& p) const;
  // The same in pixels of a width x height image showing the field of view across its shorter
  // side: x right from the left edge, y down from the top edge (pixel centres at +0.5).
  [[nodiscard]] glm::dvec2 project_px(const glm::dvec3& p, int width, int height) const;
  // The ray from the source through the centre of pixel (px, py) (unit direction).
  [[nodiscard]] glm::dvec3 pixel_ray(double px, double py, int width, int height) const;
  [[nodiscard]] double pixel_mm(int width, int height) const;  // detector mm per pixel

  // OpenGL matrices for the same projection (right-handed eye space looking down -z): vertices
  // in patient mm; the clip-space x/y of a point equals project_px's normalised coordinates.
  [[nodiscard]] glm::mat4 view_matrix() const;
  [[nodiscard]] glm::mat4 projection_matrix(int width, int height, double near_mm, double far_mm) const;

  // The collimated field: its area at the detector (cm^2) and whether a detector point is in it.
  [[nodiscard]] double field_area_cm2() const;
  [[nodiscard]] bool in_field(const glm::dvec2& detector_mm) const;

 private:
  CArmPose pose_;
  glm::dvec3 beam_{0.0, 1.0, 0.0};
  glm::dvec3 up_{0.0, 0.0, 1.0};
  glm::dvec3 right_{1.0, 0.0, 0.0};
  glm::dvec3 iso_{0.0};
  glm::dvec3 source_{0.0};
};

}  // namespace cathbox::flow
