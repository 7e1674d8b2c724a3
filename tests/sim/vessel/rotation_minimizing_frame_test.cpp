#include "vessel/rotation_minimizing_frame.hpp"

#include <cmath>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "vessel/case_generator.hpp"
#include "vessel/centerline_smoother.hpp"
#include "vessel/control_mesh_builder.hpp"

namespace cathbox::vessel {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(RotationMinimizingFrame, PlanarCurveKeepsThePlaneNormal) {
  // On a planar curve the RMF normal that starts perpendicular to the plane stays so.
  glm::dvec3 r{0, 0, 1};
  for (int i = 0; i < 36; ++i) {
    const double a0 = 2 * kPi * i / 36;
    const double a1 = 2 * kPi * (i + 1) / 36;
    r = transport_normal({std::cos(a0), std::sin(a0), 0}, {-std::sin(a0), std::cos(a0), 0}, r,
                         {std::cos(a1), std::sin(a1), 0}, {-std::sin(a1), std::cos(a1), 0});
    EXPECT_NEAR(r.z, 1.0, 1e-12);
  }
}

TEST(RotationMinimizingFrame, TwistAngleMeasuresRotationAboutTheTangent) {
  const glm::dvec3 t{0, 0, 1};
  EXPECT_NEAR(twist_angle_rad(t, {1, 0, 0}, t, {1, 0, 0}), 0.0, 1e-12);
  EXPECT_NEAR(twist_angle_rad(t, {1, 0, 0}, t, {std::cos(0.5), std::sin(0.5), 0}), 0.5, 1e-12);
  // A bend without twist: tangent z -> x, normal x -> -z.
  EXPECT_NEAR(twist_angle_rad(t, {1, 0, 0}, {1, 0, 0}, {0, 0, -1}), 0.0, 1e-12);
}

TEST(RotationMinimizingFrame, HelixRingsDoNotTwist) {
  // Property: the largest rotation between successive ring frames about the tangent is < 10 deg
  // (in fact ~0: double reflection is exact to fourth order).
  for (double pitch : {4.0, 12.0, 40.0}) {
    const VesselModel helix = CaseGenerator::helix(10.0, pitch, 3.0, 1.0, 160);
    const VesselGraph graph(helix);
    const VesselModel smoothed = smooth_centerlines(helix, graph, 3);
    const ControlMeshResult built = build_control_mesh(smoothed, graph, MeshOptions{});
    ASSERT_TRUE(built.ok()) << built.error().message;
    const auto& rings = built->rings;
    double worst = 0.0;
    double total = 0.0;
    for (std::size_t i = 0; i + 1 < rings.size(); ++i) {
      const double a = twist_angle_rad(rings[i].tangent, rings[i].normal, rings[i + 1].tangent, rings[i + 1].normal);
      worst = std::max(worst, std::abs(a));
      total += a;
    }
    EXPECT_LT(worst * 180.0 / kPi, 10.0) << "pitch " << pitch;
    EXPECT_LT(worst * 180.0 / kPi, 0.1) << "pitch " << pitch;
    // The frames are orthonormal and right-handed.
    for (const Ring& ring : rings) {
      EXPECT_NEAR(glm::dot(ring.normal, ring.tangent), 0.0, 1e-9);
      EXPECT_NEAR(glm::length(glm::cross(ring.normal, ring.binormal) - ring.tangent), 0.0, 1e-9);
    }
    (void)total;
  }
}

TEST(RotationMinimizingFrame, FramesCrossJunctionsWithoutTwist) {
  // Across a junction the child's first frame is the parent's last frame carried over the bend.
  const VesselModel y = CaseGenerator::y_bifurcation();
  const VesselGraph graph(y);
  const ControlMeshResult built = build_control_mesh(smooth_centerlines(y, graph, 3), graph, MeshOptions{});
  ASSERT_TRUE(built.ok()) << built.error().message;
  const ControlMesh& m = *built;
  const Ring& parent_last = m.rings[m.segment_first_ring[1] - 1];
  for (std::uint32_t child : {1u, 2u}) {
    const Ring& first = m.rings[m.segment_first_ring[child]];
    const double a = twist_angle_rad(parent_last.tangent, parent_last.normal, first.tangent, first.normal);
    EXPECT_LT(std::abs(a) * 180.0 / kPi, 10.0);
  }
}

}  // namespace
}  // namespace cathbox::vessel
