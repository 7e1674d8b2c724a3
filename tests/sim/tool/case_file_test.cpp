#include "tool/case_file.hpp"

#include <gtest/gtest.h>

namespace cathbox::tool {
namespace {

constexpr const char* kGood = R"(# comment
cathbox-case 1
name  demo case
tube 0  0 0 0 1.5  0 0 50 1.5
tube 1  0 0 50 1.5  10 0 80 1.2
entry 0 0 1  0 0 2
target 1 0.5
tool cath catheter
  section 900 od=1.0 ei=30 gj=23
  section 40 od=1.0 ei=4 gj=3 curve=30
  friction 0.12
  inner_diameter 0.6
  spacing 1.5 0.5 8
end
tool wire guidewire
  section 1000 od=0.36 ei=20 gj=15
  inside cath
  drag 0.02
  axial_stiffness 3000
end
)";

TEST(CaseFile, ParsesEveryStatement) {
  const CaseParse p = parse_case(kGood, "cases/demo.case");
  ASSERT_TRUE(p.value) << p.error;
  const Case& c = *p.value;
  EXPECT_EQ(c.name, "demo case");
  ASSERT_EQ(c.tubes.size(), 2u);
  EXPECT_EQ(c.tubes[1].segment, 1);
  EXPECT_DOUBLE_EQ(c.tubes[1].radius_b_mm, 1.2);
  ASSERT_TRUE(c.entry);
  EXPECT_DOUBLE_EQ(c.entry->direction.z, 1.0);  // normalised
  ASSERT_TRUE(c.target);
  EXPECT_EQ(c.target->segment, 1);
  ASSERT_EQ(c.tools.size(), 2u);
  EXPECT_EQ(c.tools[0].kind, ToolKind::kCatheter);
  EXPECT_DOUBLE_EQ(c.tools[0].length_mm(), 940.0);
  EXPECT_DOUBLE_EQ(c.tools[0].sections[1].curve_deg, 30.0);
  EXPECT_DOUBLE_EQ(c.tools[0].tip_zone_mm, 8.0);
  EXPECT_EQ(c.tools[1].inside, "cath");
  EXPECT_DOUBLE_EQ(c.tools[1].axial_stiffness_N, 3000.0);
}

TEST(CaseFile, VesselPathIsRelativeToTheCaseFile) {
  const CaseParse p = parse_case("vessel neuro.hclm\r\n", "cases/neuro.case");
  ASSERT_TRUE(p.value) << p.error;
  EXPECT_EQ(p.value->vessel_path, "cases/neuro.hclm");
  ASSERT_EQ(p.value->tools.size(), 1u);  // the default guidewire
  EXPECT_EQ(p.value->tools[0].name, "guidewire");
}

struct BadCase {
  const char* text;
  const char* error;
};

class CaseFileErrors : public ::testing::TestWithParam<BadCase> {};

TEST_P(CaseFileErrors, NameFileAndLine) {
  const CaseParse p = parse_case(GetParam().text, "x.case");
  EXPECT_FALSE(p.value);
  EXPECT_EQ(p.error, GetParam().error);
}

INSTANTIATE_TEST_SUITE_P(
    Bad, CaseFileErrors,
    ::testing::Values(
        BadCase{"vessel a.hclm\nfoo 1\n", "x.case:2: unknown keyword 'foo'"},
        BadCase{"cathbox-case 2\n", "x.case:1: unsupported case version '2' (known: 1)"},
        BadCase{"tube 0 0 0 0 1 0 0 nan 1\n", "x.case:1: tube: 'nan' is not a finite number"},
        BadCase{"tube 0 0 0 0 -1 0 0 5 1\n", "x.case:1: tube: radius must be > 0"},
        BadCase{"tube 0 0 0 0 1 0 0 5\n", "x.case:1: tube: expected 9 values, got 8"},
        BadCase{"tube 0 0 0 0 1 0 0 5 1\n", "x.case:1: analytic tubes need an 'entry'"},
        BadCase{"vessel a.hclm\nentry 0 0 0 0 0 0\n", "x.case:2: entry: direction must not be zero"},
        BadCase{"vessel a.hclm\ntarget 1 1.5\n", "x.case:2: target: fraction must be in [0, 1]"},
        BadCase{"vessel a.hclm\ntool w guidewire\nend\n", "x.case:2: tool 'w' has no section"},
        BadCase{"vessel a.hclm\ntool w wire\n", "x.case:2: tool: kind must be 'guidewire' or 'catheter', not 'wire'"},
        BadCase{"vessel a.hclm\ntool w guidewire\n section 10 od=1\nend\n",
                "x.case:3: section: od=, ei= and gj= are required"},
        BadCase{"vessel a.hclm\ntool w guidewire\n section 100 od=0.3 ei=1 gj=1\n",
                "x.case:2: tool 'w' has no 'end'"},
        BadCase{"vessel a.hclm\ntool w guidewire\n section 99999 od=0.3 ei=1 gj=1\nend\n",
                "x.case:2: tool 'w' is longer than 4000 mm"},
        BadCase{"vessel a.hclm\ntool w guidewire\n section 100 od=0.3 ei=1 gj=1\n inside c\nend\n",
                "x.case:2: tool 'w': inside unknown tool 'c'"},
        BadCase{"vessel a.hclm\ntool c catheter\n section 100 od=1 ei=1 gj=1\n inner_diameter 0.3\nend\n"
                "tool w guidewire\n section 100 od=0.36 ei=1 gj=1\n inside c\nend\n",
                "x.case:6: tool 'w' (od 0.360000 mm) does not fit in 'c'"},
        BadCase{"end\n", "x.case:1: 'end' without a tool"},
        BadCase{"name\n", "x.case:1: name: missing value"},
        BadCase{"", "x.case:0: no vessel: give 'vessel FILE' or 'tube' lines"}));

}  // namespace
}  // namespace cathbox::tool
