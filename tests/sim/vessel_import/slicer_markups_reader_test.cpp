#include "vessel_import/slicer_markups_reader.hpp"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "bad_input.hpp"

namespace cathbox::vessel_import {
namespace {

std::string example() {
  std::ifstream in(std::string(CATHBOX_SOURCE_DIR) + "/sim/vessel_import/examples/mca_bifurcation.mrk.json");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A file with one curve of the given control points and radius values.
std::string curve(const std::string& points, const std::string& radii, const std::string& extra = "") {
  return "{\n \"@schema\": \"x\",\n \"markups\": [\n  {\"type\": \"Curve\", \"name\": \"c\"" + extra +
         ",\n   \"controlPoints\": [" + points + "],\n   \"measurements\": [{\"name\": \"Radius\", \"controlPointValues\": [" +
         radii + "]}]}\n ]\n}\n";
}

TEST(SlicerMarkups, ReadsTheExampleCurvesInLps) {
  const SlicerRead read = parse_slicer_markups(example(), "mca.mrk.json");
  ASSERT_TRUE(read.ok()) << read.errors.front().to_string();
  ASSERT_EQ(read.curves.size(), 5u);
  EXPECT_EQ(read.skipped_markups, 1u);  // the point list
  EXPECT_EQ(read.curves[0].name, "Centerline curve (0)");
  // The A1 curve is stored in RAS: its first point is the ICA terminus (14, -14, 226) in LPS.
  const auto& a1 = read.curves[4].points.front();
  EXPECT_NEAR(a1.pos_mm.x, 14.0, 1e-9);
  EXPECT_NEAR(a1.pos_mm.y, -14.0, 1e-9);
  EXPECT_NEAR(read.curves[0].points.back().pos_mm.x, 14.0, 1e-9);
  EXPECT_GT(read.curves[1].points.front().radius_mm, 1.3);
}

TEST(SlicerMarkups, UnitsUndefinedPointsAndClosedCurves) {
  const std::string um = curve(R"({"position": [1000, 0, 0]}, {"position": [2000, 0, 0], "positionStatus": "undefined"},
                                 {"position": [3000, 0, 0]})",
                               "500, 500, 400", R"(, "coordinateUnits": ["um", "UCUM", "micrometer"])");
  const SlicerRead read = parse_slicer_markups(um, "u.mrk.json");
  ASSERT_TRUE(read.ok()) << read.errors.front().to_string();
  ASSERT_EQ(read.curves[0].points.size(), 2u);
  EXPECT_EQ(read.skipped_points, 1u);
  EXPECT_NEAR(read.curves[0].points[1].pos_mm.x, 3.0, 1e-12);
  EXPECT_NEAR(read.curves[0].points[1].radius_mm, 0.4, 1e-12);
  // --units overrides the file's.
  EXPECT_NEAR(parse_slicer_markups(um, "u.mrk.json", "Radius", 10.0).curves[0].points[1].pos_mm.x, 30000.0, 1e-9);
  // A closed curve comes back to its start.
  std::string closed = curve(R"({"position": [0, 0, 0]}, {"position": [10, 0, 0]}, {"position": [0, 10, 0]})", "1, 1, 1");
  closed.replace(closed.find("\"Curve\""), 7, "\"ClosedCurve\"");
  const SlicerRead loop = parse_slicer_markups(closed, "c.mrk.json");
  ASSERT_TRUE(loop.ok());
  EXPECT_EQ(loop.curves[0].points.size(), 4u);
  // Another radius measurement name.
  std::string named = curve(R"({"position": [0, 0, 0]}, {"position": [10, 0, 0]})", "1, 1");
  named.replace(named.find("\"Radius\""), 8, "\"Diameter/2\"");
  EXPECT_FALSE(parse_slicer_markups(named, "n.mrk.json").ok());
  EXPECT_TRUE(parse_slicer_markups(named, "n.mrk.json", "diameter/2").ok());
}

class SlicerBadInput : public ::testing::TestWithParam<test::BadInput> {};

TEST_P(SlicerBadInput, GivesOneClearErrorWithFileAndLine) {
  test::expect_first_error(parse_slicer_markups(GetParam().text, "bad.mrk.json").errors, "bad.mrk.json", GetParam());
}

INSTANTIATE_TEST_SUITE_P(
    Slicer, SlicerBadInput,
    ::testing::Values(
        test::BadInput{"syntax", "{\n \"markups\": [\n  {\"type\": \"Curve\",,}\n ]\n}\n", 3, "syntax error"},
        test::BadInput{"truncated", "{\n \"markups\": [\n", 3, "unexpected end of input"},
        test::BadInput{"not_object", "[1, 2]\n", 1, "expected a JSON object"},
        test::BadInput{"no_markups", "{\n \"@schema\": \"x\"\n}\n", 1, "no \"markups\" array"},
        test::BadInput{"no_curves", "{\"markups\": [\n {\"type\": \"Fiducial\", \"controlPoints\": []}\n]}\n", 1, "no curve"},
        test::BadInput{"no_radius", "{\"markups\": [\n {\"type\": \"Curve\",\n  \"controlPoints\": [{\"position\": [0,0,0]}]}\n]}\n", 2,
                "has no per-point radius"},
        test::BadInput{"radius_count", curve(R"({"position": [0, 0, 0]}, {"position": [1, 0, 0]})", "1"), 6, "1 radius values for 2 control points"},
        test::BadInput{"position", curve("{\"position\": [0, 0]}, {\"position\": [1, 0, 0]}", "1, 1"), 5, "\"position\" must be 3 numbers"},
        test::BadInput{"position_text", curve("{\"position\": [0, \"a\", 0]}, {\"position\": [1, 0, 0]}", "1, 1"), 5, "3 finite numbers"},
        test::BadInput{"system", curve("{\"position\": [0, 0, 0]}, {\"position\": [1, 0, 0]}", "1, 1", ", \"coordinateSystem\": \"XYZ\""), 4,
                "neither LPS nor RAS"},
        test::BadInput{"units", curve("{\"position\": [0, 0, 0]}, {\"position\": [1, 0, 0]}", "1, 1", ", \"coordinateUnits\": \"in\""), 4,
                "coordinateUnits"},
        test::BadInput{"deep", std::string(200, '[') + std::string(200, ']'), 1, "nested deeper than 64"},
        test::BadInput{"empty", "", 1, "unexpected end of input"}),
    test::case_name);

}  // namespace
}  // namespace cathbox::vessel_import
