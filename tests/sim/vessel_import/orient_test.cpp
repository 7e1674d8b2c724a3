// Naming the inlet and the sac (ImportOptions::inlet, ::sac; network_builder.hpp, Orient): a
// generated closed surface with a saccular aneurysm whose sac (radius 4 mm) is wider than the
// parent (1.5 mm) is rooted at the sac's end by default (the widest free end), and at the named
// inlet with the sac named "aneurysm" (sim/flow closes it) when the points are given.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <unistd.h>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "vessel/mesh_export.hpp"
#include "vessel/vessel_mesher.hpp"
#include "vessel_import/importer.hpp"

namespace cathbox::vessel_import {
namespace {

namespace fs = std::filesystem;

// The parent from x = 0 to 30 (radius 1.5), the distal parent on to (55, 10, 0) (1.2), and the
// sac: a segment from the junction to (30, -14, 0) widening to 4 mm over its last 6 mm.
vessel::VesselModel parent_with_sac() {
  vessel::VesselModel m;
  vessel::Segment parent;
  parent.id = 1;
  parent.children = {2, 3};
  for (int i = 0; i <= 15; ++i) parent.points.push_back({{2.0 * i, 0.0, 0.0}, 1.5});
  vessel::Segment distal;
  distal.id = 2;
  distal.parents = {1};
  for (int i = 0; i <= 12; ++i) distal.points.push_back({{30.0 + 2.0 * i, 0.8 * i, 0.0}, 1.2});
  vessel::Segment sac;
  sac.id = 3;
  sac.parents = {1};
  for (int i = 0; i <= 14; ++i) {
    const double y = -1.0 * i;
    sac.points.push_back({{30.0, y, 0.0}, i < 8 ? 1.2 : 1.2 + (4.0 - 1.2) * std::sin(0.25 * M_PI * (i - 7) / 3.5)});
  }
  m.segments = {parent, distal, sac};
  return m;
}

class Orient : public ::testing::Test {
 protected:
  void SetUp() override {
    const vessel::VesselSurface surface = vessel::build_vessel_surface(parent_with_sac());
    ASSERT_TRUE(surface.ok()) << surface.error;
    path_ = (fs::temp_directory_path() / ("cathbox_orient_" + std::to_string(::getpid()) + ".stl")).string();
    ASSERT_EQ(vessel::write_mesh(surface.mesh, path_), "");
  }
  void TearDown() override { fs::remove(path_); }
  std::string path_;
};

// The segment nearest p (by its points) and that distance.
std::size_t nearest_segment(const vessel::VesselModel& m, const glm::dvec3& p) {
  std::size_t best = 0;
  double d = 1e30;
  for (std::size_t i = 0; i < m.segments.size(); ++i) {
    for (const vessel::CenterlinePoint& q : m.segments[i].points) {
      if (glm::length(q.pos_mm - p) < d) {
        d = glm::length(q.pos_mm - p);
        best = i;
      }
    }
  }
  return best;
}

TEST_F(Orient, WithoutThePointsTheWidestEndTheSacIsTheRoot) {
  const ImportResult r = import_centerlines(path_);
  ASSERT_TRUE(r.ok()) << r.errors.front().to_string();
  ASSERT_EQ(r.model.segments.size(), 3u) << r.summary();
  const vessel::Segment& root = r.model.segments.front();
  EXPECT_TRUE(root.parents.empty());
  EXPECT_LT(glm::length(root.points.front().pos_mm - glm::dvec3(30, -14, 0)), 4.0) << r.summary();
  for (const vessel::Segment& s : r.model.segments) EXPECT_EQ(s.name, "");
}

TEST_F(Orient, TheNamedInletIsTheRootAndTheNamedSacIsClosed) {
  ImportOptions options;
  options.inlet = glm::dvec3(-1, 0.5, 0);
  options.sac = glm::dvec3(30, -12, 0);
  const ImportResult r = import_centerlines(path_, options);
  ASSERT_TRUE(r.ok()) << r.errors.front().to_string();
  ASSERT_EQ(r.model.segments.size(), 3u) << r.summary();
  const vessel::Segment& root = r.model.segments.front();
  EXPECT_TRUE(root.parents.empty());
  EXPECT_LT(glm::length(root.points.front().pos_mm - glm::dvec3(0, 0, 0)), 2.0) << r.summary();
  const vessel::Segment& sac = r.model.segments[nearest_segment(r.model, glm::dvec3(30, -12, 0))];
  EXPECT_EQ(sac.name, kSacName);
  EXPECT_TRUE(sac.children.empty());
  EXPECT_EQ(sac.parents, std::vector<std::int32_t>{root.id});
  EXPECT_LT(glm::length(sac.points.back().pos_mm - glm::dvec3(30, -14, 0)), 4.0);  // the sac's end is its distal end
  EXPECT_NE(r.summary().find("sac: segment " + std::to_string(sac.id)), std::string::npos) << r.summary();
}

TEST_F(Orient, ASacPointOnABranchingSegmentIsRefusedInOneLine) {
  ImportOptions options;
  options.inlet = glm::dvec3(0, 0, 0);
  options.sac = glm::dvec3(10, 0, 0);  // on the parent, which branches
  const ImportResult r = import_centerlines(path_, options);
  ASSERT_EQ(r.errors.size(), 1u);
  const std::string line = r.errors.front().to_string();
  EXPECT_EQ(line.rfind(path_ + ": --sac: the segment nearest the point (1, ", 0), 0u) << line;
  EXPECT_NE(line.find("is not blind"), std::string::npos) << line;
}

// Without --inlet the root is the widest free end, here the sac's: the entry's segment then ends
// blind and would pass as the sac (issue 31). A sac point is refused without the inlet; with it,
// the entry's segment is the parent, which branches: the same point is refused as not blind.
TEST_F(Orient, ASacWithoutAnInletIsRefusedInOneLine) {
  ImportOptions options;
  options.sac = glm::dvec3(1, 0.5, 0);  // on the entry's segment
  const ImportResult r = import_centerlines(path_, options);
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_EQ(r.errors.front().to_string(), path_ + ": " + kSacNeedsInlet);
  options.inlet = glm::dvec3(-1, 0.5, 0);
  const ImportResult named = import_centerlines(path_, options);
  ASSERT_EQ(named.errors.size(), 1u);
  const std::string line = named.errors.front().to_string();
  EXPECT_NE(line.find(": --sac: the segment nearest the point (1, "), std::string::npos) << line;
  EXPECT_NE(line.find("is not blind"), std::string::npos) << line;
}

}  // namespace
}  // namespace cathbox::vessel_import
