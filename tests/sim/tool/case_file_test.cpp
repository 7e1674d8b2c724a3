#include "scenario/case_file.hpp"

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
  ASSERT_TRUE(p) << p.error().message;
  const Case& c = *p;
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

TEST(CaseFile, ValveFrictionAndBloodForEveryToolFromTheCase) {
  const std::string text = std::string(kGood) + "valve_friction 35\nflow viscosity 4.2\n";
  CaseParse p = parse_case(text, "cases/demo.case");
  ASSERT_TRUE(p) << p.error().message;
  for (const ToolSpec& t : p->tools) {
    EXPECT_DOUBLE_EQ(t.valve_friction(), 35.0) << t.name;
    EXPECT_DOUBLE_EQ(t.blood_viscosity_mPa_s, 4.2) << t.name;
  }
  EXPECT_DOUBLE_EQ(*p->tools[1].drag_mN_s_per_mm2, 0.02);  // its own
  EXPECT_FALSE(p->tools[0].drag_mN_s_per_mm2);             // blood's
  EXPECT_NEAR(p->tools[0].drag_at(0.5), blood_drag_mN_s_per_mm2(0.5, 4.2), 1e-15);
  // A tool's own line wins; bad values name the line.
  std::string own = kGood;
  own.replace(own.find("  inside cath"), 0, "  valve_friction 5\n");
  p = parse_case(own + "valve_friction 35\n", "demo.case");
  ASSERT_TRUE(p) << p.error().message;
  EXPECT_DOUBLE_EQ(p->tools[1].valve_friction(), 5.0);
  EXPECT_DOUBLE_EQ(p->tools[0].valve_friction(), 35.0);
  EXPECT_EQ(parse_case(std::string(kGood) + "valve_friction -1\n", "demo.case").error().message,
            "demo.case:21: valve_friction must be in [0, 2000] mN");
  EXPECT_EQ(parse_case(std::string(kGood) + "valve_friction 1\nvalve_friction 2\n", "demo.case").error().message.substr(0, 13), "demo.case:22:");
  // Without a case line, the default.
  p = parse_case(kGood, "demo.case");
  EXPECT_DOUBLE_EQ(p->tools[0].valve_friction(), kDefaultValveFriction_mN);
}

TEST(CaseFile, VesselPathIsRelativeToTheCaseFile) {
  const CaseParse p = parse_case("vessel neuro.hclm\r\n", "cases/neuro.case");
  ASSERT_TRUE(p) << p.error().message;
  EXPECT_EQ(p->vessel_path, "cases/neuro.hclm");
  ASSERT_EQ(p->tools.size(), 1u);  // the default guidewire
  EXPECT_EQ(p->tools[0].name, "guidewire");
}

TEST(CaseFile, ParsesFlowSettings) {
  const CaseParse p = parse_case(
      "vessel neuro.hclm\n"
      "flow viscosity 4\n"
      "flow cardiac_output 5500\n"
      "flow cerebral_fraction 0.14\n"
      "flow pressure 100 6\n"
      "flow wall_shear_stress 1.5\n"
      "flow dispersion 0.5\n"
      "flow pulsatile 72 1.1\n"
      "flow terminals fixed\n"
      "flow inflow 1 5200\n"
      "flow outlet 16 90\n"
      "flow closed 17 0.2\n"
      "flow closed 24\n",
      "cases/x.case");
  ASSERT_TRUE(p) << p.error().message;
  const flow::FlowSettings& f = p->flow;
  EXPECT_DOUBLE_EQ(f.viscosity_mPa_s, 4.0);
  EXPECT_DOUBLE_EQ(f.cardiac_output_ml_min, 5500.0);
  EXPECT_DOUBLE_EQ(f.cerebral_fraction, 0.14);
  EXPECT_DOUBLE_EQ(f.arterial_pressure_mmHg, 100.0);
  EXPECT_DOUBLE_EQ(f.venous_pressure_mmHg, 6.0);
  EXPECT_DOUBLE_EQ(f.wall_shear_stress_Pa, 1.5);
  EXPECT_DOUBLE_EQ(f.dispersion_radii, 0.5);
  EXPECT_DOUBLE_EQ(f.heart_rate_bpm, 72.0);
  EXPECT_DOUBLE_EQ(f.pulsatility_index, 1.1);
  EXPECT_FALSE(f.calibrate_terminals);
  ASSERT_EQ(f.inflows.size(), 1u);
  EXPECT_EQ(f.inflows[0], (flow::SegmentSetting{1, 5200.0, 10}));
  ASSERT_EQ(f.outlets.size(), 1u);
  EXPECT_EQ(f.outlets[0], (flow::SegmentSetting{16, 90.0, 11}));
  ASSERT_EQ(f.closed.size(), 2u);
  EXPECT_EQ(f.closed[0], (flow::SegmentSetting{17, 0.2, 12}));
  EXPECT_DOUBLE_EQ(f.closed[1].value, flow::FlowSettings{}.sac_exchange_fraction);
  EXPECT_EQ(f.source, "cases/x.case");
  // Without flow lines: the defaults.
  const CaseParse d = parse_case("vessel neuro.hclm\n", "cases/y.case");
  ASSERT_TRUE(d);
  flow::FlowSettings defaults;
  defaults.source = "cases/y.case";
  EXPECT_EQ(d->flow, defaults);
}

TEST(CaseFile, ParsesViewsAndRealisticMode) {
  const CaseParse p = parse_case("vessel neuro.hclm\nview right_working -25 15\nview towne 0 30\nrealistic\n", "x.case");
  ASSERT_TRUE(p) << p.error().message;
  ASSERT_EQ(p->views.size(), 2u);
  EXPECT_EQ(p->views[0].name, "right_working");
  EXPECT_EQ(p->views[0].lao_deg, -25.0);
  EXPECT_EQ(p->views[0].cranial_deg, 15.0);
  EXPECT_TRUE(p->realistic);
  EXPECT_FALSE(parse_case("vessel neuro.hclm\n", "x.case")->realistic);
}

struct BadCase {
  const char* text;
  const char* error;
};

class CaseFileErrors : public ::testing::TestWithParam<BadCase> {};

TEST_P(CaseFileErrors, NameFileAndLine) {
  const CaseParse p = parse_case(GetParam().text, "x.case");
  ASSERT_FALSE(p);
  EXPECT_EQ(p.error().message, GetParam().error);
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
        BadCase{"vessel a.hclm\ntool w wire\n", "x.case:2: tool: kind must be 'guidewire', 'catheter' or 'coil', not 'wire'"},
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
        BadCase{"vessel a.hclm\ntool a catheter\n section 100 od=1 ei=1 gj=1\n inner_diameter 0.8\n inside b\nend\n"
                "tool b catheter\n section 100 od=0.7 ei=1 gj=1\n inner_diameter 0.5\n inside a\nend\n",
                "x.case:2: tool 'a': the tools it runs in run inside it"},
        BadCase{"vessel a.hclm\ntool k coil\n section 100 od=0.3 ei=1 gj=1\n section 40 od=0.25 ei=0.02 gj=0.02 shape=ring loop=5\n",
                "x.case:4: section: shape must be 'helix' or 'complex', not 'ring'"},
        BadCase{"vessel a.hclm\ntool k coil\n section 40 od=0.25 ei=0.02 gj=0.02 shape=helix\n",
                "x.case:3: section: shape= and loop= go together"},
        BadCase{"vessel a.hclm\ntool k coil\n section 40 od=0.25 ei=0.02 gj=0.02 shape=helix loop=30\n",
                "x.case:3: section: loop diameter must be in [2, 20] mm"},
        BadCase{"vessel a.hclm\ntool w guidewire\n section 40 od=0.25 ei=0.02 gj=0.02 shape=helix loop=4\n",
                "x.case:3: section: shape= is for coil tools"},
        BadCase{"vessel a.hclm\ntool w guidewire\n section 40 od=0.25 ei=0.02 gj=0.02\n detach 10\n",
                "x.case:4: detach is for coil tools"},
        BadCase{"vessel a.hclm\ntool k coil\n section 40 od=0.25 ei=0.02 gj=0.02\nend\n",
                "x.case:2: coil 'k' needs 'detach MM' shorter than the tool"},
        BadCase{"vessel a.hclm\ntool k coil\n section 40 od=0.25 ei=0.02 gj=0.02\n detach 400\n",
                "x.case:4: detach: coil length must be in (0, 300] mm"},
        BadCase{"vessel a.hclm\ntool w guidewire\n section 40 od=0.25 ei=0.02 gj=0.02\n next_coil 10 od=0.25 ei=0.02 gj=0.02 shape=helix loop=4\n",
                "x.case:4: next_coil is for coil tools"},
        BadCase{"vessel a.hclm\ntool k coil\n section 100 od=0.3 ei=1 gj=1\n section 40 od=0.25 ei=0.02 gj=0.02 shape=helix loop=4\n detach 40\n"
                " next_coil 400 od=0.25 ei=0.02 gj=0.02 shape=helix loop=4\n",
                "x.case:6: next_coil: coil length must be in (0, 300] mm"},
        BadCase{"vessel a.hclm\ntool k coil\n section 100 od=0.3 ei=1 gj=1\n section 40 od=0.25 ei=0.02 gj=0.02 shape=helix loop=4\n detach 40\n"
                " next_coil 30 od=0.25 ei=0.02 gj=0.02\n",
                "x.case:6: next_coil: shape= and loop= are required"},
        BadCase{"vessel a.hclm\ntool k coil\n section 100 od=0.3 ei=1 gj=1\n section 40 od=0.25 ei=0.02 gj=0.02 shape=helix loop=4\n detach 40\n"
                " next_coil 30 od=0.25 ei=0.02 shape=helix loop=4\n",
                "x.case:6: next_coil: od=, ei= and gj= are required"},
        BadCase{"vessel a.hclm\ntool m catheter\n section 300 od=0.7 ei=2 gj=1.6\n inner_diameter 0.45\nend\ntool k coil\n section 100 od=0.3 ei=1 gj=1\n"
                " section 40 od=0.25 ei=0.02 gj=0.02 shape=helix loop=4\n detach 40\n next_coil 30 od=0.5 ei=0.02 gj=0.02 shape=helix loop=4\n"
                " inside m\nend\n",
                "x.case:6: tool 'k' (od 0.500000 mm) does not fit in 'm'"},
        // Each next coil as the tool it makes once loaded, as a record's reader checks it: the
        // tip zone grows by the next coil's length past its 500 mm limit.
        BadCase{"vessel a.hclm\ntool k coil\n section 600 od=0.3 ei=1 gj=1\n section 20 od=0.25 ei=0.02 gj=0.02 shape=helix loop=4\n"
                " detach 20\n spacing 2 0.5 480\n next_coil 300 od=0.25 ei=0.02 gj=0.02 shape=helix loop=4\nend\n",
                "x.case:2: with its next coil 1: tool 'k': tip zone must be in [0, 500] mm"},
        BadCase{"name\n", "x.case:1: name: missing value"},
        BadCase{"", "x.case:0: no vessel: give 'vessel FILE' or 'tube' lines"},
        BadCase{"vessel a.hclm\nflow\n",
                "x.case:2: flow: missing setting (viscosity cardiac_output cerebral_fraction pressure wall_shear_stress "
                "dispersion pulsatile terminals inflow outlet closed)"},
        BadCase{"vessel a.hclm\nflow speed 3\n",
                "x.case:2: flow: unknown setting 'speed' (known: viscosity cardiac_output cerebral_fraction pressure "
                "wall_shear_stress dispersion pulsatile terminals inflow outlet closed)"},
        BadCase{"vessel a.hclm\nflow viscosity 0.1\n", "x.case:2: flow viscosity: 0.1 is not in [0.5, 20] mPa.s"},
        BadCase{"vessel a.hclm\nflow viscosity x\n", "x.case:2: flow viscosity: 'x' is not a finite number"},
        BadCase{"vessel a.hclm\nflow viscosity 3 4\n", "x.case:2: flow viscosity: expected 1 value, got 2"},
        BadCase{"vessel a.hclm\nflow viscosity 3\nflow viscosity 4\n", "x.case:3: flow viscosity given twice"},
        BadCase{"vessel a.hclm\nflow pressure 80 90\n", "x.case:2: flow pressure: 90 is not in [0, 50] mmHg"},
        BadCase{"vessel a.hclm\nflow pressure 30 30\n", "x.case:2: flow pressure: venous must be below arterial pressure"},
        BadCase{"vessel a.hclm\nflow pulsatile 70 3\n", "x.case:2: flow pulsatile: 3 is not in [0, 2]"},
        BadCase{"vessel a.hclm\nflow cerebral_fraction 0\n", "x.case:2: flow cerebral_fraction: 0 is not in (0, 0.5]"},
        BadCase{"vessel a.hclm\nflow terminals loose\n",
                "x.case:2: flow terminals: expected 'calibrated' or 'fixed', not 'loose'"},
        BadCase{"vessel a.hclm\nflow outlet 3.5 100\n", "x.case:2: flow outlet: segment id must be a 32-bit integer"},
        BadCase{"vessel a.hclm\nflow outlet 3 0\n", "x.case:2: flow outlet: 0 is not in (0, 40000] mL/min"},
        BadCase{"vessel a.hclm\nflow outlet 3\n", "x.case:2: flow outlet: expected 2 values, got 1"},
        BadCase{"vessel a.hclm\nflow closed 3 2\n", "x.case:2: flow closed: 2 is not in [0, 1]"},
        BadCase{"vessel a.hclm\nflow closed 3\nflow outlet 3 50\n",
                "x.case:3: flow outlet: segment 3 already given on line 2"},
        BadCase{"vessel a.hclm\nview a 10\n", "x.case:2: view: expected 3 values, got 2"},
        BadCase{"vessel a.hclm\nview a 10 0\nview a 20 0\n", "x.case:3: view 'a' defined twice"},
        BadCase{"vessel a.hclm\nview a 130 0\n", "x.case:2: view: LAO/RAO angle must be within +-120 degrees"},
        BadCase{"vessel a.hclm\nview a 0 90\n", "x.case:2: view: cranial/caudal angle must be within +-60 degrees"},
        BadCase{"vessel a.hclm\nrealistic yes\n", "x.case:2: realistic: expected 0 values, got 1"},
        BadCase{"vessel a.hclm\nrealistic\nrealistic\n", "x.case:3: realistic given twice"},
        BadCase{"vessel a.hclm\nflow inflow 3 50\nflow inflow 3 60\n",
                "x.case:3: flow inflow: segment 3 already given on line 2"}));

}  // namespace
}  // namespace cathbox::tool
