// Junctions the convex hull of their rings cannot mesh (branches overlap: too short or too close
// to part, folding back, a spur starting inside its parent) are meshed by the spherical-hull
// fallback: the surface is closed, manifold and outward, the summary names the junction, and the
// branches keep their radius away from it. With the fallback off they are an error, as before.
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "radius_probe.hpp"
#include "vessel/case_library.hpp"
#include "vessel/control_mesh_builder.hpp"
#include "vessel/hclm.hpp"
#include "vessel/mesh_analysis.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::vessel {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A segment block of straight points from a to b (n points, radius r).
std::string straight(int id, const std::string& parents, const std::string& children, glm::dvec3 a, glm::dvec3 b,
                     int n, double r) {
  std::string out = "g " + std::to_string(id) + "\np " + parents + "\nc " + children + "\nn " + std::to_string(n) + "\n";
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 p = a + (b - a) * (static_cast<double>(i) / (n - 1));
    out += "v " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + " " + std::to_string(r) + "\n";
  }
  return out;
}

VesselModel parse(const std::string& text) {
  const HclmReadResult read = read_hclm(text);
  EXPECT_TRUE(read.ok()) << (read.ok() ? "" : read.errors.front().to_string());
  return read.model;
}

// A child folding straight back along its parent (the tubes coincide).
VesselModel fold_back() {
  return parse("s 2\ng 1\np 0\nc 1 2\nn 3\nv 0 0 0 2\nv 0 0 1 2\nv 0 0 2 2\n"
               "g 2\np 1 1\nc 0\nn 3\nv 0 0 2 2\nv 0 0.01 1 2\nv 0 0.02 0 2\n");
}

// Two 0.5 mm branches 10 degrees apart and 3 mm (6 radii) long off a 1 mm parent: they cannot part.
VesselModel narrow_short() {
  const glm::dvec3 fork(0.0, 0.0, 20.0);
  const double half = 5.0 * kPi / 180.0;
  return parse("s 3\n" + straight(1, "0", "2 2 3", {0, 0, 0}, fork, 21, 1.0) +
               straight(2, "1 1", "0", fork, fork + 3.0 * glm::dvec3(std::sin(half), 0, std::cos(half)), 7, 0.5) +
               straight(3, "1 1", "0", fork, fork + 3.0 * glm::dvec3(-std::sin(half), 0, std::cos(half)), 7, 0.5));
}

// A skeleton's spur: a 1 mm branch 2 mm long leaving a 3 mm vessel's axis, ending inside its lumen.
VesselModel spur() {
  const glm::dvec3 mid(0.0, 0.0, 30.0);
  return parse("s 3\n" + straight(1, "0", "2 2 3", {0, 0, 0}, mid, 16, 3.0) +
               straight(2, "1 1", "0", mid, {0, 0, 60}, 16, 3.0) +
               straight(3, "1 1", "0", mid, mid + glm::dvec3(2.0, 0.0, 0.0), 5, 1.0));
}

struct Defect {
  const char* name;
  VesselModel (*model)();
};

class JunctionFallback : public ::testing::TestWithParam<Defect> {};

TEST_P(JunctionFallback, IsAnErrorWithoutTheFallback) {
  MeshOptions off;
  off.junction_fallback = false;
  const VesselSurface refused = build_vessel_surface(GetParam().model(), off);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error.find("junction 0 (segments"), std::string::npos) << refused.error;
}

TEST_P(JunctionFallback, MeshesClosedAndNamesTheJunction) {
  const VesselModel model = GetParam().model();
  const VesselSurface surface = build_vessel_surface(model);
  ASSERT_TRUE(surface.ok()) << surface.error;
  ASSERT_EQ(surface.control.fallback_junctions.size(), 1u);
  EXPECT_EQ(surface.control.fallback_junctions[0].junction, 0u);
  const std::string summary = fallback_summary(surface.control);
  EXPECT_NE(summary.find("1 junction meshed by the spherical-hull fallback: junction 0 (segments"), std::string::npos)
      << summary;
  const MeshAnalysis a = analyze_mesh(surface.mesh);
  EXPECT_TRUE(a.closed()) << a.boundary_edges << " boundary edges";
  EXPECT_TRUE(a.manifold()) << a.nonmanifold_edges << " non-manifold edges, " << a.nonmanifold_vertices << " vertices";
  EXPECT_TRUE(a.consistently_oriented()) << a.misoriented_edges << " misoriented edges";
  EXPECT_EQ(a.degenerate_triangles, 0u);
  EXPECT_EQ(a.euler_characteristic, surface.euler_characteristic);
  EXPECT_GT(a.signed_volume_mm3, 0.0);
  std::printf("%s: %zu self-intersecting triangle pairs\n", GetParam().name, count_self_intersections(surface.mesh, 100000));
  for (int m : {4, 6, 16}) {  // any ring size
    MeshOptions options;
    options.ring_points = m;
    const VesselSurface other = build_vessel_surface(model, options);
    ASSERT_TRUE(other.ok()) << "M " << m << ": " << other.error;
    const MeshAnalysis b = analyze_mesh(other.mesh);
    EXPECT_TRUE(b.closed() && b.manifold() && b.consistently_oriented()) << "M " << m;
    EXPECT_EQ(b.euler_characteristic, other.euler_characteristic) << "M " << m;
  }
}

// The vessels around the junction keep their input radius (within 3 %, the mesher's figure on
// clean geometry) from one radius beyond their first ring to one before their last: the fallback
// changes the junction's patch only. Not for the fold-back, whose tubes coincide (no lumen to
// measure).
class JunctionFallbackRadius : public ::testing::TestWithParam<Defect> {};

TEST_P(JunctionFallbackRadius, BranchesKeepTheirRadiusAwayFromTheJunction) {
  const VesselModel model = GetParam().model();
  const VesselSurface surface = build_vessel_surface(model);
  ASSERT_TRUE(surface.ok()) << surface.error;
  const test::ProfileError e = test::worst_along_segments(model, surface);
  std::printf("%s: radius worst %+.2f %% over %d cuts\n", GetParam().name, 100.0 * e.worst, e.samples);
  EXPECT_GT(e.samples, 20);
  EXPECT_LT(std::abs(e.worst), 0.03) << "at arc " << e.worst_arc << ": " << e.worst_surface << " for " << e.worst_input;
}

const auto defect_name = [](const auto& param_info) { return std::string(param_info.param.name); };

INSTANTIATE_TEST_SUITE_P(Defects, JunctionFallback,
                         ::testing::Values(Defect{"fold_back", fold_back}, Defect{"narrow_short", narrow_short},
                                           Defect{"spur", spur}),
                         defect_name);
INSTANTIATE_TEST_SUITE_P(Defects, JunctionFallbackRadius,
                         ::testing::Values(Defect{"narrow_short", narrow_short}, Defect{"spur", spur}), defect_name);

// The type III arch: its brachiocephalic trunk cannot part from the arch within its length, so
// that junction is the fallback's, and the whole head-and-neck tree meshes closed.
TEST(JunctionFallbackLibrary, ArchTypeThreeMeshesClosed) {
  const VesselModel model = library_model(*library_case("arch_type3"));
  const VesselSurface surface = build_vessel_surface(model);
  ASSERT_TRUE(surface.ok()) << surface.error;
  EXPECT_FALSE(surface.control.fallback_junctions.empty());
  std::printf("arch_type3: %s\n", fallback_summary(surface.control).c_str());
  const MeshAnalysis a = analyze_mesh(surface.mesh);
  EXPECT_TRUE(a.closed() && a.manifold() && a.consistently_oriented());
  EXPECT_EQ(a.euler_characteristic, surface.euler_characteristic);
  EXPECT_GT(a.signed_volume_mm3, 0.0);
  const test::ProfileError e = test::worst_along_segments(model, surface);
  std::printf("arch_type3: radius worst %+.2f %% over %d cuts\n", 100.0 * e.worst, e.samples);
  // The tall arch's trunk leaves the ascending aorta steeply: the fallback's patch still does not
  // cross itself or the tubes.
  EXPECT_EQ(count_self_intersections(surface.mesh, 100), 0u);
  EXPECT_LT(std::abs(e.worst), 0.03) << "at arc " << e.worst_arc << ": " << e.worst_surface << " for " << e.worst_input;
}

}  // namespace
}  // namespace cathbox::vessel
