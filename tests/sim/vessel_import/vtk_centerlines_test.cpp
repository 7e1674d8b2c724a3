#include "vessel_import/vtk_centerlines.hpp"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "vessel_import/importer.hpp"

namespace cathbox::vessel_import {
namespace {

std::string examples() { return std::string(CATHBOX_SOURCE_DIR) + "/sim/vessel_import/examples/"; }

std::string write_temp(const std::string& name, const std::string& content) {
  const std::filesystem::path dir = std::filesystem::path(CATHBOX_BINARY_DIR) / "vessel_import_test_files";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

// A legacy POLYDATA file with two polylines sharing a point and a radius array called `array`.
std::string legacy(const std::string& array = "MaximumInscribedSphereRadius", const std::string& extra = "") {
  return "# vtk DataFile Version 4.2\nt\nASCII\nDATASET POLYDATA\nPOINTS 5 float\n"
         "0 0 0\n0 0 5\n0 0 10\n4 0 16\n-4 0 16\nLINES 2 8\n3 0 1 2\n3 2 3 4\n" + extra +
         "POINT_DATA 5\nSCALARS " + array + " double 1\nLOOKUP_TABLE default\n1 1 1 0.8 0.8\n";
}

TEST(VtkCenterlines, ReadsTheVmtkExamples) {
  const ImportResult vtp = import_centerlines(examples() + "carotid_bifurcation_centerlines.vtp");
  ASSERT_TRUE(vtp.ok()) << vtp.errors.front().to_string();
  EXPECT_EQ(vtp.polylines, 2u);
  EXPECT_EQ(vtp.model.segments.size(), 3u);  // CCA trunk, ICA, ECA
  EXPECT_EQ(vtp.network.junctions, 1u);
  EXPECT_EQ(vtp.network.overlapping, 1u);
  EXPECT_EQ(vtp.filter.changed, 3u);  // the two collapsed outlet radii and the bad ECA sample
  const ImportResult vtk = import_centerlines(examples() + "vertebrobasilar_tracts.vtk");
  ASSERT_TRUE(vtk.ok()) << vtk.errors.front().to_string();
  EXPECT_EQ(vtk.polylines, 3u);  // 8 tracts rejoined into 3 centrelines
  EXPECT_EQ(vtk.model.segments.size(), 5u);  // two vertebrals, basilar, two posterior cerebrals
  EXPECT_EQ(vtk.network.junctions, 2u);
}

TEST(VtkCenterlines, PlainPolylinesAndTheRadiusArrayName) {
  const std::string path = write_temp("two_lines.vtk", legacy());
  const VtkRead read = read_vtk_centerlines(path, "", false);
  ASSERT_TRUE(read.ok()) << read.errors.front().to_string();
  EXPECT_EQ(read.arrays.lines.size(), 2u);
  EXPECT_EQ(read.arrays.radius_array, "MaximumInscribedSphereRadius");
  const std::string other = write_temp("other_name.vtk", legacy("Thickness"));
  const VtkRead missing = read_vtk_centerlines(other, "", false);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.errors.front().message.find("point arrays: Thickness"), std::string::npos) << missing.errors.front().to_string();
  EXPECT_TRUE(read_vtk_centerlines(other, "Thickness", false).ok());
  const VtkRead wrong_name = read_vtk_centerlines(other, "Radius", false);
  ASSERT_FALSE(wrong_name.ok());
  EXPECT_NE(wrong_name.errors.front().message.find("no point array 'Radius'"), std::string::npos);
  EXPECT_NE(missing.errors.front().message.find("tried MaximumInscribedSphereRadius, Radius, radius, radii;"),
            std::string::npos) << missing.errors.front().to_string();
}

// DBiharMesher's centrelines (BlueFern/DBiharMesher, data/*_Centreline.vtk) name their radius
// array `radii`: found without --radius-array.
TEST(VtkCenterlines, RadiiArrayOfDBiharMesherIsFound) {
  const std::string path = write_temp("radii.vtk", legacy("radii"));
  const VtkRead read = read_vtk_centerlines(path, "", false);
  ASSERT_TRUE(read.ok()) << read.errors.front().to_string();
  EXPECT_EQ(read.arrays.radius_array, "radii");
  const ImportResult r = import_centerlines(path);
  ASSERT_TRUE(r.ok()) << r.errors.front().to_string();
  EXPECT_NE(r.summary().find("radius from 'radii'"), std::string::npos) << r.summary();
}

struct BadVtk {
  const char* name;
  std::string content;
  bool xml;
  const char* message;
  int line;
};

class VtkBadInput : public ::testing::TestWithParam<BadVtk> {};

TEST_P(VtkBadInput, OneLineNamingTheFileAndNothingOnStderr) {
  const std::string path = write_temp(std::string(GetParam().name) + (GetParam().xml ? ".vtp" : ".vtk"), GetParam().content);
  ::testing::internal::CaptureStderr();
  const ImportResult r = import_centerlines(path);
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(err, "") << "VTK printed to stderr";
  ASSERT_FALSE(r.ok());
  const std::string line = r.errors.front().to_string();
  EXPECT_EQ(line.rfind(path + ":", 0), 0u) << line;
  EXPECT_EQ(line.find('\n'), std::string::npos) << line;
  EXPECT_NE(line.find(GetParam().message), std::string::npos) << line;
  if (GetParam().line > 0) {
    EXPECT_EQ(r.errors.front().line, GetParam().line) << line;
  }
}

const std::string kPoints = "# vtk DataFile Version 4.2\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0\n0 0 5\n0 0 10\n";

INSTANTIATE_TEST_SUITE_P(
    Vtk, VtkBadInput,
    ::testing::Values(
        BadVtk{"empty", "", false, "VTK: Premature EOF reading first line!", 0},
        BadVtk{"text", "hello, this is not a VTK file\n", false, "VTK: Unrecognized file type: hello, this is not a VTK file", 0},
        BadVtk{"binary_garbage", std::string("\x00\xff\x13\x37garbage\x01\x02", 12), false, "VTK: Unrecognized file type", 0},
        BadVtk{"grid", "# vtk DataFile Version 4.2\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\n", false,
               "not a legacy VTK POLYDATA file", 0},
        BadVtk{"truncated", kPoints.substr(0, kPoints.size() - 6), false, "VTK: Error reading ascii data", 0},
        BadVtk{"no_lines", kPoints + "POINT_DATA 3\nSCALARS Radius double 1\nLOOKUP_TABLE default\n1 1 1\n", false, "no line cells", 0},
        BadVtk{"bad_ids", kPoints + "LINES 1 3\n2 0 7\nPOINT_DATA 3\nSCALARS Radius double 1\nLOOKUP_TABLE default\n1 1 1\n", false,
               "line cell 0 uses point 7 of 3", 0},
        BadVtk{"vector_radius", kPoints + "LINES 1 4\n3 0 1 2\nPOINT_DATA 3\nVECTORS Radius double\n1 1 1\n1 1 1\n1 1 1\n", false,
               "3 components", 0},
        BadVtk{"xml_broken", "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\">\n<PolyData>\n<Piece NumberOfPoints=\"3\"\n</VTKFile>\n", true,
               "not well-formed", 5},
        BadVtk{"xml_other_type", "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\"><ImageData></ImageData></VTKFile>\n",
               true, "not a VTK XML PolyData file", 0}),
    [](const ::testing::TestParamInfo<BadVtk>& p) { return std::string(p.param.name); });

TEST(VtkCenterlines, MissingFile) {
  const ImportResult r = import_centerlines("/nonexistent/centerlines.vtp");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.errors.front().to_string(), "/nonexistent/centerlines.vtp: cannot open file");
}

TEST(VtkCenterlines, ArraysCheckedBeforeUse) {
  PolylineArrays a;
  a.points = {{0, 0, 0}, {0, 0, 1}};
  a.radius = {1.0, 1.0};
  a.lines = {{0, 1, 2}};
  EXPECT_NE(centerline_polylines(a, "f", 1.0).errors.front().message.find("uses point 2 of 2"), std::string::npos);
  a.lines = {{0, 1}};
  a.radius = {1.0};
  EXPECT_NE(centerline_polylines(a, "f", 1.0).errors.front().message.find("1 values for 2 points"), std::string::npos);
  a.radius = {1.0, 1.0};
  a.centerline_ids = {0, 1};
  a.tract_ids = {0};
  EXPECT_FALSE(centerline_polylines(a, "f", 1.0).ok());
}

}  // namespace
}  // namespace cathbox::vessel_import
