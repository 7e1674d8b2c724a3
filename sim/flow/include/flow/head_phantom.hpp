#pragma once
// The patient around the vessels, for fluoroscopic images: a head-and-neck phantom of analytic
// shapes (ellipsoids, elliptic cylinders along z, boxes, each optionally cut by z planes) in
// the bundled cases' patient coordinates (x left, y anterior, z superior; the circle of Willis
// near z 235). Each shape adds delta_mu (1/mm) to what it lies in, so nested shapes make
// shells: the skull is a bone ellipsoid minus a smaller one inside the scalp. The line integral
// of mu along a ray (Beer-Lambert exponent) is the sum of delta_mu times the ray's chord
// through each shape, exact for these shapes. Shapes of the same material must not overlap
// (the soft tissue is a head ellipsoid above z 140, a neck cylinder below it, a chest below).
//
// What it holds (HeadPhantom::neuro): head and neck soft tissue with the airway, skull vault
// (6 mm tables) cut at the skull base, brain, skull base and petrous ridges, maxilla, mandible
// (a U) and rami, the atlas ring, the dens, the cervical vertebral bodies C2-C7 with
// transverse processes and posterior arches, the chest with lungs, sternum, clavicles and
// thoracic vertebrae. Sizes are typical adult values; positions fit the bundled neuro case (carotids
// in front of the spine, vertebral arteries beside it, the siphons above the skull base).
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "flow/c_arm.hpp"
#include "flow/xray_material.hpp"

namespace cathbox::flow {

enum class ShapeKind : unsigned char { kEllipsoid, kCylinderZ, kBox };

struct PhantomShape {
  std::string name;
  ShapeKind kind = ShapeKind::kEllipsoid;
  glm::dvec3 center_mm{0.0};
  glm::dvec3 half_mm{1.0};      // semi-axes (ellipsoid), rx ry and half height (cylinder), half extents (box)
  double z_min_mm = -1e9;       // cut below this plane
  double z_max_mm = 1e9;        // cut above this plane
  double delta_mu_per_mm = 0.0; // added to the material it lies in
  double y_min_mm = -1e9;       // cut behind this plane (an open U, e.g. the mandible)
};

class HeadPhantom {
 public:
  HeadPhantom() = default;
  explicit HeadPhantom(std::vector<PhantomShape> shapes) : shapes_(std::move(shapes)) {}

  // The phantom for the bundled neuro cases at an effective energy.
  [[nodiscard]] static HeadPhantom neuro(double keV = kDefaultEffectiveEnergy_keV);

  [[nodiscard]] const std::vector<PhantomShape>& shapes() const { return shapes_; }
  // Line integral of mu along the ray origin + t * direction, t >= 0 (direction unit length).
  [[nodiscard]] double path_mu(const glm::dvec3& origin, const glm::dvec3& direction) const;
  // Chord length (mm) of such a ray through one shape.
  [[nodiscard]] static double chord_mm(const PhantomShape& s, const glm::dvec3& origin, const glm::dvec3& direction);

  // The path integral for every pixel centre of a width x height image of the C-arm (row 0 at
  // the top): what the detector would see without vessels and tools. Shapes are only
  // evaluated inside their projected bounding box.
  [[nodiscard]] std::vector<float> project(const CArm& carm, int width, int height) const;
  // Mean transmission exp(-path) over the central quarter of the collimated field (a 15 x 15
  // grid of rays): what the automatic dose-rate control measures.
  [[nodiscard]] double central_transmission(const CArm& carm) const;

 private:
  std::vector<PhantomShape> shapes_;
};

}  // namespace cathbox::flow
