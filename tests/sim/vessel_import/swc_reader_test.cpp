#include "vessel_import/swc_reader.hpp"

#include <gtest/gtest.h>

#include "bad_input.hpp"

#include "vessel_import/importer.hpp"

namespace cathbox::vessel_import {
namespace {

TEST(SwcReader, ReadsSamplesAnyOrderCommentsAndCrLf) {
  const SwcRead read = parse_swc(
      "# header\r\n\r\n3 0 0 0 2 0.8 2 # inline\r\n1 1 0 0 0 1.0 -1\n2 0 0 0 1 0.9 1\n4 0 1 0 3 0.7 3\n5 0 -1 0 3 0.7 3\n",
      "t.swc");
  ASSERT_TRUE(read.ok()) << read.errors.front().to_string();
  ASSERT_EQ(read.samples.size(), 5u);
  EXPECT_EQ(read.samples[0].id, 3);
  EXPECT_EQ(read.samples[0].line, 3);
  const SwcBranches b = swc_branches(read.samples, 2.0);
  ASSERT_EQ(b.branches.size(), 3u);  // 3 -> 4, 3 -> 5 (3 branches), then the root 1 -> 3
  EXPECT_EQ(b.branches[0].from, 3u);
  EXPECT_EQ(b.branches[0].to, 4u);
  EXPECT_DOUBLE_EQ(b.branches[0].line.points.front().radius_mm, 1.4);  // sample 4's radius, scaled by 2
  const Branch& root = b.branches[2];
  EXPECT_EQ(root.from, 1u);
  EXPECT_EQ(root.to, 3u);
  ASSERT_EQ(root.line.points.size(), 3u);
  EXPECT_DOUBLE_EQ(root.line.points.back().pos_mm.z, 4.0);  // scaled by 2
  EXPECT_DOUBLE_EQ(root.line.points.front().radius_mm, 2.0);
}

class SwcBadInput : public ::testing::TestWithParam<test::BadInput> {};

TEST_P(SwcBadInput, GivesOneClearErrorWithFileAndLine) {
  test::expect_first_error(parse_swc(GetParam().text, "bad.swc").errors, "bad.swc", GetParam());
}

INSTANTIATE_TEST_SUITE_P(
    Swc, SwcBadInput,
    ::testing::Values(test::BadInput{"columns", "1 0 0 0 0 1 -1\n2 0 0 0 1 1\n", 2, "expected 7 columns"},
                      test::BadInput{"number", "1 0 0 0 0 1 -1\n2 0 0 x 1 1 1\n", 2, "y 'x' is not a finite number"},
                      test::BadInput{"nan", "1 0 0 0 0 nan -1\n", 1, "radius 'nan' is not a finite number"},
                      test::BadInput{"id", "-4 0 0 0 0 1 -1\n", 1, "not a non-negative integer"},
                      test::BadInput{"parent", "1 0 0 0 0 1 -2\n", 1, "parent '-2'"},
                      test::BadInput{"duplicate", "1 0 0 0 0 1 -1\n2 0 0 0 1 1 1\n2 0 0 0 2 1 1\n", 3, "already used on line 2"},
                      test::BadInput{"missing_parent", "1 0 0 0 0 1 -1\n2 0 0 0 1 1 9\n", 2, "parent 9 is not defined"},
                      test::BadInput{"self", "1 0 0 0 0 1 1\n", 1, "its own parent"},
                      test::BadInput{"loop", "1 0 0 0 0 1 -1\n2 0 0 0 1 1 3\n3 0 0 0 2 1 2\n", 2, "own ancestor"},
                      test::BadInput{"empty", "# nothing\n", 0, "no samples"}),
    test::case_name);

TEST(SwcReader, ImportsTheExampleTree) {
  const ImportResult r = import_centerlines(std::string(CATHBOX_SOURCE_DIR) + "/sim/vessel_import/examples/cortical_tree.swc");
  ASSERT_TRUE(r.ok()) << r.errors.front().to_string();
  EXPECT_EQ(r.model.segments.size(), 31u);  // every branch between two branching samples
  EXPECT_EQ(r.network.junctions, 15u);
  EXPECT_EQ(r.network.cycles, 0u);
  EXPECT_NE(r.summary().find("SWC"), std::string::npos);
}

}  // namespace
}  // namespace cathbox::vessel_import
