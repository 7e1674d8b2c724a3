// A case naming its own wall (`surface FILE`, scenario/case_surface.hpp): the world collides with
// that surface, not the one meshed from the HCLM, and keeps the HCLM's graph for targets; bad
// surfaces are refused in one line naming the file.
#include "scenario/case_surface.hpp"

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include <gtest/gtest.h>

#include "scenario/case_file.hpp"
#include "scenario/case_wall.hpp"
#include "scenario/case_world.hpp"
#include "tool/mesh_wall.hpp"
#include "vessel/case_generator.hpp"
#include "vessel/hclm.hpp"
#include "vessel/mesh_wire.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::tool {
namespace {

class CaseSurface : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("cathbox_case_surface_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    model_ = vessel::CaseGenerator::y_bifurcation();
    ASSERT_TRUE(vessel::save_hclm(model_, (dir_ / "y.hclm").string()).empty());
    // A coarser surface than the case would mesh (level 1, not 2): which one the world uses shows.
    vessel::MeshOptions coarse;
    coarse.subdivision_level = 1;
    vessel::VesselSurface s = vessel::build_vessel_surface(model_, coarse);
    ASSERT_TRUE(s.ok()) << s.error;
    lumen_ = std::move(s.mesh);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& bytes) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }
  CaseParse parse(const std::string& surface_line) {
    return parse_case("cathbox-case 1\nvessel y.hclm\n" + surface_line + "target 2 1.0\n", (dir_ / "y.case").string());
  }

  std::filesystem::path dir_;
  vessel::VesselModel model_;
  vessel::SurfaceMesh lumen_;
};

TEST_F(CaseSurface, TheWorldCollidesWithTheCasesSurfaceAndKeepsTheGraph) {
  write("lumen.cbxmesh", vessel::encode_mesh_wire(lumen_));
  const CaseParse c = parse("surface lumen.cbxmesh\n");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(c->surface_path, (dir_ / "lumen.cbxmesh").string());
  WorldBuild world = build_world(*c);
  ASSERT_TRUE(world) << world.error().message;
  ASSERT_NE((*world)->mesh(), nullptr);
  EXPECT_TRUE((*world)->surface_given());
  EXPECT_EQ((*world)->mesh()->triangle_count(), lumen_.triangle_count());
  const auto* wall = dynamic_cast<const MeshWall*>(&(*world)->wall());
  ASSERT_NE(wall, nullptr);
  EXPECT_EQ(wall->tree().stats().triangles + wall->tree().stats().degenerate_dropped, lumen_.triangle_count());
  ASSERT_NE((*world)->model(), nullptr);  // the HCLM's graph: the target is on segment 2
  EXPECT_TRUE((*world)->target().has_value());

  // Without the line, the world meshes the HCLM (level 2: four times the triangles).
  WorldBuild meshed = build_world(*parse(""));
  ASSERT_TRUE(meshed) << meshed.error().message;
  EXPECT_FALSE((*meshed)->surface_given());
  EXPECT_EQ((*meshed)->mesh()->triangle_count(), 4 * lumen_.triangle_count());
}

TEST_F(CaseSurface, BadSurfacesAreRefusedInOneLineNamingTheFile) {
  const auto error_of = [&](const std::string& name) {
    WorldBuild w = build_world(*parse("surface " + name + "\n"));
    EXPECT_FALSE(w);
    return w ? std::string() : w.error().message;
  };
  EXPECT_NE(error_of("missing.cbxmesh").find("missing.cbxmesh: cannot open"), std::string::npos);
  write("lumen.ply", "ply\nformat ascii 1.0\n");
  EXPECT_NE(error_of("lumen.ply").find("lumen.ply: byte 0"), std::string::npos);
  EXPECT_NE(error_of("lumen.ply").find("--surface-out FILE.cbxmesh"), std::string::npos);

  vessel::SurfaceMesh open = lumen_;  // one triangle short: no longer closed
  open.triangles.resize(open.triangles.size() - 3);
  open.triangle_regions.pop_back();
  write("open.cbxmesh", vessel::encode_mesh_wire(open));
  EXPECT_NE(error_of("open.cbxmesh").find("open.cbxmesh: the surface is not closed (3 boundary edges)"), std::string::npos);

  vessel::SurfaceMesh inside_out = lumen_;
  for (std::size_t t = 0; t < inside_out.triangle_count(); ++t) std::swap(inside_out.triangles[3 * t + 1], inside_out.triangles[3 * t + 2]);
  write("inverted.cbxmesh", vessel::encode_mesh_wire(inside_out));
  EXPECT_NE(error_of("inverted.cbxmesh").find("not oriented outward"), std::string::npos);

  vessel::SurfaceMesh other = lumen_;  // a surface of a vessel with a segment 77
  other.triangle_regions[5] = {vessel::RegionKind::kSegment, 77};
  write("other.cbxmesh", vessel::encode_mesh_wire(other));
  EXPECT_NE(error_of("other.cbxmesh").find("other.cbxmesh: triangle 5 belongs to segment 77"), std::string::npos);
}

TEST_F(CaseSurface, ASurfaceNeedsAVessel) {
  const CaseParse bare = parse_case("cathbox-case 1\nsurface lumen.cbxmesh\ntube 1 0 0 0 2 0 0 50 2\nentry 0 0 1 0 0 1\n", "x.case");
  ASSERT_FALSE(bare);
  EXPECT_NE(bare.error().message.find("a 'surface' needs a 'vessel'"), std::string::npos);
  const CaseParse twice = parse("surface a.cbxmesh\nsurface b.cbxmesh\n");
  ASSERT_FALSE(twice);
  EXPECT_NE(twice.error().message.find("y.case:4: surface given twice"), std::string::npos);
  // A `wall` without a radius takes the vessel's: tubes have none to give.
  const CaseParse tubes = parse_case("cathbox-case 1\nwall cervical\ntube 1 0 0 0 2 0 0 50 2\nentry 0 0 1 0 0 1\n", "x.case");
  ASSERT_FALSE(tubes);
  EXPECT_NE(tubes.error().message.find("x.case:4: a 'wall' without a radius takes the 'vessel''s"), std::string::npos);
}

// A balloon re-meshes the wall from the HCLM's centrelines at each inflation (session_setup's
// angioplasty unit), which would drop the given surface: the case is refused at its surface line.
TEST_F(CaseSurface, ASurfaceCaseCannotCarryABalloon) {
  const std::string balloon =
      "tool b catheter\n  section 1400 od=0.9 ei=60 gj=45\n  inner_diameter 0.45\n"
      "  balloon length=20 from_tip=3 nominal=6 burst=14 chart=2:4.6,6:5.0,10:5.3,14:5.5\nend\n";
  const CaseParse with = parse("surface lumen.cbxmesh\n" + balloon);
  ASSERT_FALSE(with);
  EXPECT_NE(with.error().message.find("y.case:3: a 'surface' case cannot carry a balloon (tool 'b')"), std::string::npos)
      << with.error().message;
  const CaseParse without = parse(balloon);  // the same balloon on the meshed wall
  EXPECT_TRUE(without) << without.error().message;
}

// The case's surface takes the compliant wall (issue 29 on issue 31's surfaces): the contact's
// stiffness at the graph's radius, and the surface itself, moved along its normals by each
// segment's Laplace distension, is what the tools meet.
TEST_F(CaseSurface, ASurfaceTakesTheCompliantWall) {
  write("lumen.cbxmesh", vessel::encode_mesh_wire(lumen_));
  const CaseParse c = parse("surface lumen.cbxmesh\nwall intracranial\n");
  ASSERT_TRUE(c) << c.error().message;
  ASSERT_TRUE(c->wall.has_value());
  EXPECT_EQ(c->wall->radius_mm, 0.0);
  WorldBuild world = build_world(*c);
  ASSERT_TRUE(world) << world.error().message;
  const vessel::VesselModel* read = (*world)->source_model();
  ASSERT_NE(read, nullptr);
  EXPECT_EQ(case_wall_radius_mm(*c->wall, read), median_radius_mm(model_));
  const std::unique_ptr<CaseWallField> field = make_case_wall_field(&*c->wall, (*world)->wall(), read);
  ASSERT_NE(field, nullptr);
  ASSERT_EQ(field->distension().segment_count(), model_.segments.size());
  // A probe on the parent's axis, half way: the wall moves out by that segment's P / k.
  const vessel::Segment& parent = model_.segments.front();
  const glm::dvec3 mid = parent.points[parent.points.size() / 2].pos_mm;
  WallProbe probe;
  probe.center_mm = mid;
  probe.radius_mm = 0.1;
  probe.range_mm = 10.0;
  WallHint hint;
  WallContact rest, moved;
  ASSERT_TRUE(field->wall().probe(probe, hint, rest));
  field->set_pressure_kPa(4.0);
  ASSERT_TRUE(field->wall().probe(probe, hint, moved));
  ASSERT_GE(rest.segment, 0);
  const std::size_t index = *model_.index_of(rest.segment);
  EXPECT_NEAR(moved.distance_mm - rest.distance_mm, 4.0 * field->distension().compliance_mm_per_kPa(index), 1e-9);
  EXPECT_GT(moved.distance_mm, rest.distance_mm);
  EXPECT_NE(field->wall().revision(), 0u);  // a rod at rest against it is solved again
}

}  // namespace
}  // namespace cathbox::tool
