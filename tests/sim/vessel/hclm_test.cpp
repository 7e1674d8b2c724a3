#include "vessel/hclm.hpp"

#include <string>

#include <gtest/gtest.h>

#include "vessel/case_generator.hpp"
#include "vessel/point_range.hpp"
#include "vessel_test_support.hpp"

namespace cathbox::vessel {
namespace {

constexpr const char* kTwoSegments =
    "s 2\n"
    "g 99\n"
    "l main\n"
    "f 60.000000\n"
    "p 0\n"
    "c 1 100\n"
    "n 3\n"
    "v -6.673064 12.703399 -47.877568 4.990000\n"
    "v -7.873580 11.309175 -44.813852 4.940000\n"
    "v -9.074098 9.914953 -41.750136 4.890000\n"
    "g 100\n"
    "l branch\n"
    "f 30\n"
    "p 1 99\n"
    "c 0\n"
    "n 2\n"
    "v -9.074098 9.914953 -41.750136 3.0\n"
    "v -10 8 -38 2.9\n";

TEST(Hclm, ReadsTheThesisExampleFormat) {
  const HclmReadResult r = read_hclm(kTwoSegments, "a1.hclm");
  ASSERT_TRUE(r.ok()) << r.errors.front().to_string();
  ASSERT_EQ(r.model.segments.size(), 2u);
  const Segment& main = r.model.segments[0];
  EXPECT_EQ(main.id, 99);
  EXPECT_EQ(main.name, "main");
  EXPECT_DOUBLE_EQ(main.flow, 60.0);
  EXPECT_TRUE(main.parents.empty());
  EXPECT_EQ(main.children, std::vector<std::int32_t>{100});
  ASSERT_EQ(main.points.size(), 3u);
  EXPECT_DOUBLE_EQ(main.points[1].pos_mm.y, 11.309175);
  EXPECT_DOUBLE_EQ(main.points[2].radius_mm, 4.89);
  EXPECT_EQ(r.model.segments[1].parents, std::vector<std::int32_t>{99});
}

TEST(Hclm, ReadsTheThesisCatheterFileVerbatim) {
  // cases/seed_catheter.hclm is Appendix A.2 as printed: trailing spaces, a blank line of spaces.
  const HclmReadResult r = load_hclm(test::case_path("seed_catheter"));
  ASSERT_TRUE(r.ok()) << r.errors.front().to_string();
  ASSERT_EQ(r.model.segments.size(), 1u);
  const Segment& s = r.model.segments[0];
  EXPECT_EQ(s.id, 0);
  EXPECT_EQ(s.name, "test");
  ASSERT_EQ(s.points.size(), 11u);
  EXPECT_DOUBLE_EQ(s.points.front().pos_mm.x, 1.20);
  EXPECT_DOUBLE_EQ(s.points.back().pos_mm.y, 1.58);
  EXPECT_DOUBLE_EQ(s.points.back().radius_mm, 0.03);
}

TEST(Hclm, ToleratesCrlfBlankLinesTabsAndSpaces) {
  std::string text;
  for (char ch : std::string(kTwoSegments)) {
    if (ch == '\n') text += "  \t\r\n\r\n";
    else if (ch == ' ') text += " \t ";
    else text += ch;
  }
  const HclmReadResult messy = read_hclm("\r\n  \n" + text, "messy.hclm");
  ASSERT_TRUE(messy.ok()) << messy.errors.front().to_string();
  EXPECT_EQ(messy.model, read_hclm(kTwoSegments).model);
}

TEST(Hclm, NamesKeepInnerSpaces) {
  std::string text = kTwoSegments;
  text.replace(text.find("l main"), 6, "l  left  middle cerebral ");
  const HclmReadResult r = read_hclm(text);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.model.segments[0].name, "left  middle cerebral");
}

TEST(Hclm, WriteThenReadIsLossless) {
  std::vector<VesselModel> models;
  for (const std::string& name : CaseGenerator::case_names()) models.push_back(CaseGenerator::make_case(name));
  models.push_back(CaseGenerator::random_tree(7));
  models.push_back(CaseGenerator::random_graph(3, 3));
  models.push_back(read_hclm(kTwoSegments).model);
  // Awkward numbers: shortest round-trip forms, tiny magnitudes, the edges of the body's range
  // (point_range.hpp), negative zero.
  VesselModel odd = read_hclm(kTwoSegments).model;
  odd.segments[0].points[0] = {{0.1, -1e-300, 1234.56789123456789}, 1e-7};
  odd.segments[0].points[1] = {{-0.0, 1.0 / 3.0, -kMaxCoordinate_mm}, kMaxRadius_mm};
  odd.segments[0].flow = -3.0e-5;
  models.push_back(odd);
  for (const VesselModel& model : models) {
    const std::string text = write_hclm(model);
    const HclmReadResult back = read_hclm(text, "written.hclm");
    ASSERT_TRUE(back.ok()) << back.errors.front().to_string();
    EXPECT_EQ(back.model, model);
    EXPECT_EQ(write_hclm(back.model), text);
  }
}

TEST(Hclm, BundledCaseFilesMatchTheGenerator) {
  for (const std::string& name : CaseGenerator::case_names()) {
    const HclmReadResult r = load_hclm(test::case_path(name));
    ASSERT_TRUE(r.ok()) << name << ": " << r.errors.front().to_string();
    EXPECT_EQ(r.model, CaseGenerator::make_case(name)) << name << " is stale: run `cathbox vessel generate --all cases`";
  }
}

struct BadInput {
  const char* what;
  std::string text;
  int line;
  const char* message_part;
};

// A valid two-segment file with one line replaced (1-based line numbers).
std::string with_line(int line, const std::string& replacement) {
  std::string text = kTwoSegments;
  std::size_t start = 0;
  for (int i = 1; i < line; ++i) start = text.find('\n', start) + 1;
  const std::size_t end = text.find('\n', start);
  return text.substr(0, start) + replacement + text.substr(end);
}

// Shown by CTest/GoogleTest instead of the parameter's bytes.
void PrintTo(const BadInput& bad, std::ostream* os) { *os << bad.what; }

class HclmBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(HclmBadInput, GivesOneClearErrorWithFileAndLine) {
  const BadInput& bad = GetParam();
  const HclmReadResult r = read_hclm(bad.text, "bad.hclm");
  ASSERT_FALSE(r.ok()) << bad.what;
  // Some diagnostic names this problem at this line; every diagnostic is one line.
  const Diagnostic* match = nullptr;
  std::string all;
  for (const Diagnostic& d : r.errors) {
    EXPECT_EQ(d.file, "bad.hclm");
    EXPECT_EQ(d.to_string().find('\n'), std::string::npos);
    all += d.to_string() + "\n";
    if (d.line == bad.line && d.message.find(bad.message_part) != std::string::npos) match = &d;
  }
  ASSERT_NE(match, nullptr) << bad.what << ", got:\n" << all;
  EXPECT_EQ(match->to_string().rfind("bad.hclm:" + std::to_string(bad.line) + ": ", 0), 0u) << match->to_string();
}

INSTANTIATE_TEST_SUITE_P(
    Hclm, HclmBadInput,
    ::testing::Values(
        BadInput{"unknown label", with_line(4, "x 60"), 4, "unknown label 'x'"},
        BadInput{"label glued to value", with_line(4, "f60"), 4, "unknown label"},
        BadInput{"fewer v lines than n", with_line(7, "n 4"), 7, "'n 4' but only 3"},
        BadInput{"more v lines than n", with_line(7, "n 2"), 10, "more 'v' lines"},
        BadInput{"s disagrees with segments", with_line(1, "s 3"), 1, "file has 2 segments"},
        BadInput{"p count vs ids", with_line(14, "p 2 99"), 14, "parent count 2 but 1 ids"},
        BadInput{"c count vs ids", with_line(6, "c 1 100 101"), 6, "child count 1 but 2 ids"},
        BadInput{"child does not list parent", with_line(14, "p 0"), 6, "does not list 99 as parent"},
        BadInput{"parent does not list child", with_line(6, "c 0"), 14, "does not list 100 as child"},
        BadInput{"unknown child id", with_line(6, "c 2 100 7"), 6, "unknown child id 7"},
        BadInput{"duplicate id", with_line(11, "g 99"), 11, "duplicate segment id 99"},
        BadInput{"nan coordinate", with_line(9, "v nan 1 2 3"), 9, "not finite"},
        BadInput{"infinite radius", with_line(9, "v 1 1 2 inf"), 9, "not finite"},
        BadInput{"not a number", with_line(9, "v 1 1 2x 3"), 9, "'2x' is not a number"},
        BadInput{"coordinate beyond the body", with_line(9, "v 1 1 5.6e214 3"), 9, "z 5.6e+214 mm is outside ±2000 mm"},
        BadInput{"radius of a metre", with_line(9, "v 1 1 2 1000"), 9, "radius 1000 mm is above 100 mm"},
        BadInput{"zero radius", with_line(9, "v 1 1 2 0"), 9, "must be > 0"},
        BadInput{"negative radius", with_line(9, "v 1 1 2 -4"), 9, "must be > 0"},
        BadInput{"too few fields", with_line(9, "v 1 1 2"), 9, "takes 4 numbers"},
        BadInput{"one point", "s 1\ng 1\np 0\nc 0\nn 1\nv 0 0 0 1\n", 5, "at least 2"},
        BadInput{"absurd count", "s 1\ng 1\np 0\nc 0\nn 999999999\nv 0 0 0 1\nv 0 0 1 1\n", 5, "'n 999999999' but only 2"},
        BadInput{"absurd segment count", "s 99999999999\n", 1, "not a count"},
        BadInput{"negative count", with_line(7, "n -3"), 7, "not a count"},
        BadInput{"self parent", with_line(14, "p 2 99 100"), 14, "lists itself"},
        BadInput{"id out of range", with_line(11, "g 4294967296"), 11, "not a 32-bit integer"},
        BadInput{"v before n", "s 1\ng 1\np 0\nc 0\nv 0 0 0 1\nn 0\n", 5, "before the 'n' line"},
        BadInput{"line outside a segment", "s 1\nn 2\n", 2, "outside a segment"},
        BadInput{"missing s", "g 1\np 0\nc 0\nn 2\nv 0 0 0 1\nv 0 0 1 1\n", 1, "'s' line"},
        BadInput{"second n", with_line(10, "n 3"), 10, "second 'n' line"},
        BadInput{"missing p", with_line(5, ""), 2, "no 'p' line"},
        BadInput{"child far from parent", with_line(17, "v 40 40 40 3.0"), 6, "starts"}),
    [](const ::testing::TestParamInfo<BadInput>& param_info) {
      std::string name;
      for (char ch : std::string(param_info.param.what)) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
      return name;
    });

TEST(Hclm, ReportsEveryProblemInTheOrderFound) {
  const std::string text = "s 3\ng 1\np 0\nc 0\nn 2\nv 0 0 0 1\nv 0 0 nan 1\nq\ng 2\np 0\nc 0\nn 2\nv 0 0 0 -1\nv 0 0 1 1\n";
  const HclmReadResult r = read_hclm(text, "many.hclm");
  ASSERT_EQ(r.errors.size(), 4u);
  EXPECT_EQ(r.errors[0].line, 7);
  EXPECT_EQ(r.errors[1].line, 8);
  EXPECT_EQ(r.errors[2].line, 13);
  EXPECT_EQ(r.errors[3].line, 1);  // 's 3' but 2 segments: known only at the end
}

TEST(Hclm, HugeCountsDoNotAllocate) {
  // 2^31-1 points declared, two given: the reader must answer quickly with one error.
  const HclmReadResult r = read_hclm("s 1\ng 1\np 0\nc 0\nn 2147483647\nv 0 0 0 1\nv 0 0 1 1\n");
  ASSERT_FALSE(r.ok());
  EXPECT_LT(r.model.segments.at(0).points.capacity(), 1000u);
}

TEST(Hclm, ErrorListIsCapped) {
  std::string text = "s 1\ng 1\np 0\nc 0\nn 2\nv 0 0 0 1\nv 0 0 1 1\n";
  for (int i = 0; i < 5000; ++i) text += "zz\n";
  EXPECT_EQ(read_hclm(text).errors.size(), 100u);
}

TEST(Hclm, MissingFileIsOneDiagnostic) {
  const HclmReadResult r = load_hclm("/nonexistent/dir/x.hclm");
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_EQ(r.errors[0].to_string(), "/nonexistent/dir/x.hclm: cannot open file");
}

TEST(Hclm, ValidateModelAppliesTheSameRules) {
  VesselModel model = read_hclm(kTwoSegments).model;
  EXPECT_TRUE(validate_model(model).empty());
  model.segments[1].points[0].radius_mm = 0.0;
  model.segments[0].children.push_back(555);
  const std::vector<Diagnostic> errors = validate_model(model, "mem");
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_EQ(errors[0].to_string(), "mem: segment 100 has a radius <= 0");
  EXPECT_EQ(errors[1].to_string(), "mem: unknown child id 555");
  // A model built in memory with a point beyond the body's range.
  VesselModel far = read_hclm(kTwoSegments).model;
  far.segments[0].points[1].pos_mm.y = -3.0e5;
  const std::vector<Diagnostic> range = validate_model(far, "mem");
  ASSERT_EQ(range.size(), 1u);
  EXPECT_EQ(range[0].to_string(), "mem: segment 99 point 1: y -300000 mm is outside ±2000 mm");
}

}  // namespace
}  // namespace cathbox::vessel
