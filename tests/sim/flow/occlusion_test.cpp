// Clots in the flow network: occlusion, collaterals, reperfusion, the angiographic cut-off,
// and the eTICI grade of the reperfused territory.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "flow/contrast_transport.hpp"
#include "flow/reperfusion.hpp"
#include "flow_test_support.hpp"

namespace cathbox::flow {
namespace {

using test::build_or_fail;
using test::load_model;

std::uint32_t index_of(const vessel::VesselModel& m, std::int32_t id) { return static_cast<std::uint32_t>(*m.index_of(id)); }

double segment_length_mm(const vessel::VesselModel& m, std::uint32_t i) { return CenterlineLocator(m).length_mm(i); }

// A clot filling the middle of a segment: `length_mm`, or the segment less 1 mm each side.
Clot clot_in(const vessel::VesselModel& m, std::int32_t id, double length_mm, double open_fraction = 0.0) {
  const std::uint32_t i = index_of(m, id);
  const double len = std::min(length_mm, segment_length_mm(m, i) - 2.0);
  return Clot{i, 0.5 * (segment_length_mm(m, i) - len), len, kReferenceComposition, open_fraction};
}

double outlet_flow(const FlowNetwork& net, std::uint32_t segment) {
  for (const Terminal& t : net.terminals()) {
    if (t.segment == segment && t.role == EndRole::kOutlet) return t.flow_ml_min;
  }
  ADD_FAILURE() << "no outlet on segment " << segment;
  return 0.0;
}

// Neuro case ids: 20 left ICA, 21 left ICA terminus, 22 left M1, 23/24 left M2 superior /
// inferior, 25 left A1.
constexpr std::int32_t kLeftIca = 20, kLeftIcaT = 21, kLeftM1 = 22, kLeftM2s = 23, kLeftM2i = 24, kLeftA1 = 25;

// The test: flow to the territory within 5 % of zero while occluded (collaterals
// aside: the bundled model has no leptomeningeal anastomoses into the MCA), within 5 % of
// baseline after a complete removal; Kirchhoff still holds.
TEST(Occlusion, M1ClotStarvesTheMcaTerritoryAndRemovalRestoresIt) {
  const vessel::VesselModel model = load_model("cases/neuro.hclm");
  auto net = build_or_fail(model);
  ASSERT_TRUE(net);
  const std::uint32_t m2s = index_of(model, kLeftM2s), m2i = index_of(model, kLeftM2i);
  const double base = outlet_flow(*net, m2s) + outlet_flow(*net, m2i);
  const double right_mca = outlet_flow(*net, index_of(model, 16)) + outlet_flow(*net, index_of(model, 17));
  ASSERT_GT(base, 50.0);
  const std::vector<Terminal> open = net->terminals();

  // MCA occlusions average 15.4 mm (Clin Neuroradiol 2014); the model's M1 is shorter.
  const Clot clot = clot_in(model, kLeftM1, 13.0);
  ASSERT_TRUE(net->occlude(std::vector<Clot>{clot}));
  const double occluded = outlet_flow(*net, m2s) + outlet_flow(*net, m2i);
  EXPECT_LT(occluded, 0.05 * base);
  std::printf("left MCA outlets: open %.1f mL/min, M1 occluded %.2g mL/min\n", base, occluded);
  EXPECT_GE(occluded, 0.0);
  EXPECT_LT(test::kirchhoff_residual(*net), 1e-9);
  EXPECT_NEAR(net->total_inflow_ml_min(), 5000.0, 1e-6 * 5000.0);
  // The prescribed inflow goes elsewhere: the other territories gain.
  EXPECT_GT(outlet_flow(*net, index_of(model, 16)) + outlet_flow(*net, index_of(model, 17)), right_mca);

  // The target territory and its grade.
  const auto territory = TargetTerritory::find(open, net->terminals());
  ASSERT_TRUE(territory) << territory.error().message;
  EXPECT_EQ(territory->outlets().size(), 2u);
  EXPECT_LT(territory->reperfused_fraction(net->terminals()), 0.01);
  EXPECT_EQ(territory->grade(net->terminals()), Etici::k0);

  ASSERT_TRUE(net->occlude({}));
  const double restored = outlet_flow(*net, m2s) + outlet_flow(*net, m2i);
  EXPECT_NEAR(restored, base, 0.05 * base);
  EXPECT_NEAR(restored, base, 1e-9 * base);  // the open network exactly
  EXPECT_EQ(territory->grade(net->terminals()), Etici::k3);
}

// A clot that leaves part of the lumen open lets through flow by Poiseuille's law in the open
// channel: the partial grades fall between.
TEST(Occlusion, PartialClotGivesPartialReperfusion) {
  const vessel::VesselModel model = load_model("cases/neuro.hclm");
  auto net = build_or_fail(model);
  ASSERT_TRUE(net);
  const std::vector<Terminal> open = net->terminals();
  ASSERT_TRUE(net->occlude(std::vector<Clot>{clot_in(model, kLeftM1, 13.0)}));
  const auto territory = TargetTerritory::find(open, net->terminals());
  ASSERT_TRUE(territory);
  double last = -1.0;
  for (double open_fraction : {0.01, 0.05, 0.1, 0.2, 0.4}) {
    ASSERT_TRUE(net->occlude(std::vector<Clot>{clot_in(model, kLeftM1, 13.0, open_fraction)}));
    const double f = territory->reperfused_fraction(net->terminals());
    EXPECT_GT(f, last) << open_fraction;
    EXPECT_LT(f, 1.0) << open_fraction;
    std::printf("open %.2f of the lumen: reperfused %.1f %%, eTICI %s\n", open_fraction, 100.0 * f,
                std::string(etici_label(territory->grade(net->terminals()))).c_str());
    last = f;
  }
  EXPECT_GT(last, 0.5);  // 40 % of the lumen open over 13 mm passes most of the flow
}

// A carotid-T occlusion (the terminus and the origins of the M1 and the A1): the MCA falls to
// ~0; the ACA beyond the anterior communicating artery is fed from the other side through it (a
// collateral in the model's circle of Willis), so it is not part of the hypoperfused
// territory.
TEST(Occlusion, CarotidTerminusClotStarvesTheMcaWhileTheAcommFeedsTheAca) {
  const vessel::VesselModel model = load_model("cases/neuro.hclm");
  auto net = build_or_fail(model);
  ASSERT_TRUE(net);
  const std::vector<Terminal> open = net->terminals();
  const std::uint32_t t_seg = index_of(model, kLeftIcaT);
  const std::vector<Clot> t_clot{Clot{t_seg, 0.0, segment_length_mm(model, t_seg), kReferenceComposition, 0.0},
                                 Clot{index_of(model, kLeftM1), 0.0, 4.0, kReferenceComposition, 0.0},
                                 Clot{index_of(model, kLeftA1), 0.0, 3.0, kReferenceComposition, 0.0}};
  ASSERT_TRUE(net->occlude(t_clot));
  const auto territory = TargetTerritory::find(open, net->terminals());
  ASSERT_TRUE(territory);
  for (const TerritoryOutlet& o : territory->outlets()) {
    const std::string& name = model.segments[open[o.terminal].segment].name;
    EXPECT_NE(name.find("left_middle_cerebral"), std::string::npos) << name;
    EXPECT_LT(o.occluded_ml_min, 0.05 * o.baseline_ml_min) << name;
    std::printf("carotid-T target outlet %s: open %.1f, occluded %.2g mL/min\n", name.c_str(), o.baseline_ml_min, o.occluded_ml_min);
  }
  EXPECT_EQ(territory->outlets().size(), 2u);
  const std::uint32_t a2 = index_of(model, 36);
  ASSERT_EQ(model.segments[a2].name, "left_anterior_cerebral_a2");
  EXPECT_GT(outlet_flow(*net, a2), 0.95 * outlet_flow(*build_or_fail(model), a2));
  EXPECT_EQ(territory->grade(net->terminals()), Etici::k0);
  ASSERT_TRUE(net->occlude({}));
  EXPECT_EQ(territory->grade(net->terminals()), Etici::k3);
}

// A balloon guide inflated in the cervical ICA arrests its flow (< 1 % of baseline); the M1 clot
// then holds back almost no pressure head (the distal ICA is fed backwards through the circle
// of Willis at low pressure); deflation restores the flow exactly.
TEST(Occlusion, BalloonGuideArrestsTheCarotidFlow) {
  const vessel::VesselModel model = load_model("cases/neuro.hclm");
  auto net = build_or_fail(model);
  ASSERT_TRUE(net);
  const std::uint32_t ica = index_of(model, kLeftIca), m1 = index_of(model, kLeftM1);
  const double base = net->segments()[ica].flow_mm3_s;
  const Clot clot = clot_in(model, kLeftM1, 13.0);
  ASSERT_TRUE(net->occlude(std::vector<Clot>{clot}));
  const double head_open = net->node_pressure_Pa(net->segments()[m1].start_node) - net->node_pressure_Pa(net->segments()[m1].end_node);
  ASSERT_TRUE(net->occlude(std::vector<Clot>{clot}, std::vector<FlowArrest>{{ica}}));
  EXPECT_LT(std::abs(net->segments()[ica].flow_mm3_s), 0.01 * base);
  EXPECT_LT(test::kirchhoff_residual(*net), 1e-9);
  const double head_arrested = net->node_pressure_Pa(net->segments()[m1].start_node) - net->node_pressure_Pa(net->segments()[m1].end_node);
  std::printf("left ICA %.1f mL/min, arrested %.2g; pressure across the M1 clot %.0f Pa, arrested %.0f Pa\n", base * 0.06,
              net->segments()[ica].flow_mm3_s * 0.06, head_open, head_arrested);
  EXPECT_LT(head_arrested, head_open);
  EXPECT_EQ(net->arrests().size(), 1u);
  ASSERT_FALSE(net->occlude({}, std::vector<FlowArrest>{{9999}}));
  ASSERT_TRUE(net->occlude({}));
  EXPECT_NEAR(net->segments()[ica].flow_mm3_s, base, 1e-9 * base);
}

// Fluoroscopy: an injection in the ICA opacifies the M2s through an open M1; with the M1
// occluded the contrast stops at the clot (what passes is the clot's Darcy leak, < 0.1 % of the
// ICA's concentration), and removal restores the filling.
TEST(Occlusion, ContrastStopsAtTheClot) {
  const vessel::VesselModel model = load_model("cases/neuro.hclm");
  auto net = build_or_fail(model);
  ASSERT_TRUE(net);
  const std::uint32_t ica = index_of(model, kLeftIca), m2s = index_of(model, kLeftM2s);
  const auto run = [&](const FlowNetwork& n) {
    ContrastTransport t(n);
    EXPECT_EQ(t.inject({ica, 0.4 * t.locator().length_mm(ica), 0.0}, Injection{6.0, 3.0, 300.0}), "");
    for (int i = 0; i < 150; ++i) t.step();  // 1.5 s
    return std::pair{t.max_concentration(ica), t.max_concentration(m2s)};
  };
  const auto [ica_open, m2_open] = run(*net);
  EXPECT_GT(m2_open, 0.3 * ica_open);
  ASSERT_TRUE(net->occlude(std::vector<Clot>{clot_in(model, kLeftM1, 13.0)}));
  const auto [ica_occ, m2_occ] = run(*net);
  EXPECT_GT(ica_occ, 0.5 * ica_open);
  EXPECT_LT(m2_occ, 1e-3 * ica_occ);
  std::printf("peak mgI/mL: ICA %.1f, M2 open %.1f, M2 behind the clot %.2g\n", ica_occ, m2_open, m2_occ);
  ASSERT_TRUE(net->occlude({}));
  EXPECT_NEAR(run(*net).second, m2_open, 1e-9 * m2_open);
  // A transport made while occluded takes the reopened flows with refresh_flows() (a session's
  // pass): the same filling as one made on the open network.
  ASSERT_TRUE(net->occlude(std::vector<Clot>{clot_in(model, kLeftM1, 13.0)}));
  ContrastTransport t(*net);
  ASSERT_TRUE(net->occlude({}));
  t.refresh_flows();
  EXPECT_EQ(t.inject({ica, 0.4 * t.locator().length_mm(ica), 0.0}, Injection{6.0, 3.0, 300.0}), "");
  for (int i = 0; i < 150; ++i) t.step();
  EXPECT_NEAR(t.max_concentration(m2s), m2_open, 1e-9 * m2_open);
}

TEST(Occlusion, RejectsBadClotsAndChangesNothing) {
  const vessel::VesselModel model = load_model("cases/neuro.hclm");
  auto net = build_or_fail(model);
  ASSERT_TRUE(net);
  const double before = net->segments()[index_of(model, kLeftM1)].flow_mm3_s;
  const auto rejects = [&](Clot c, const std::string& what) {
    const base::Status<> s = net->occlude(std::vector<Clot>{c});
    ASSERT_FALSE(s) << what;
    EXPECT_NE(s.error().message.find(what), std::string::npos) << s.error().message;
    EXPECT_EQ(net->segments()[index_of(model, kLeftM1)].flow_mm3_s, before);
    EXPECT_TRUE(net->clots().empty());
  };
  Clot c = clot_in(model, kLeftM1, 5.0);
  c.segment = 9999;
  rejects(c, "no segment index 9999");
  c = clot_in(model, kLeftM1, 5.0);
  c.length_mm = 1000.0;
  rejects(c, "must lie within segment 22");
  c = clot_in(model, kLeftM1, 5.0);
  c.open_fraction = 1.0;
  rejects(c, "open fraction");
  c.open_fraction = 0.0;
  c.composition = {80.0, 30.0};
  rejects(c, "exceed 100");
  const Clot a = clot_in(model, kLeftM1, 5.0);
  const base::Status<> s = net->occlude(std::vector<Clot>{a, a});
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("overlap"), std::string::npos);
}

// eTICI bands (Liebeskind et al., JNIS 2019) against hand-computed fractions: two outlets of
// baseline 100 and 50 mL/min, occluded 0 and 10; now 60 and 30 -> (100 * 0.6 + 50 * 0.5) / 150
// = 85 / 150 = 56.7 % -> 2b50.
TEST(Reperfusion, GradesHandComputedFractions) {
  EXPECT_EQ(etici_from_fraction(0.0), Etici::k0);
  EXPECT_EQ(etici_from_fraction(0.0, true), Etici::k1);
  EXPECT_EQ(etici_from_fraction(0.01), Etici::k2a);
  EXPECT_EQ(etici_from_fraction(0.49), Etici::k2a);
  EXPECT_EQ(etici_from_fraction(0.50), Etici::k2b50);
  EXPECT_EQ(etici_from_fraction(0.66), Etici::k2b50);
  EXPECT_EQ(etici_from_fraction(0.67), Etici::k2b67);
  EXPECT_EQ(etici_from_fraction(0.89), Etici::k2b67);
  EXPECT_EQ(etici_from_fraction(0.90), Etici::k2c);
  EXPECT_EQ(etici_from_fraction(0.99), Etici::k2c);
  EXPECT_EQ(etici_from_fraction(1.0), Etici::k3);
  EXPECT_EQ(etici_from_fraction(2.0), Etici::k3);
  EXPECT_EQ(etici_from_fraction(std::stod("nan")), Etici::k0);
  EXPECT_EQ(etici_label(Etici::k2b67), "2b67");
  EXPECT_TRUE(at_least(Etici::k3, Etici::k2c));
  EXPECT_FALSE(at_least(Etici::k2b67, Etici::k2c));

  std::vector<Terminal> open(3), occluded(3), now(3);
  for (std::vector<Terminal>* v : {&open, &occluded, &now}) {
    for (Terminal& t : *v) t.role = EndRole::kOutlet;
  }
  open[0].flow_ml_min = 100.0, occluded[0].flow_ml_min = 0.0, now[0].flow_ml_min = 60.0;
  open[1].flow_ml_min = 50.0, occluded[1].flow_ml_min = 10.0, now[1].flow_ml_min = 30.0;
  open[2].flow_ml_min = 80.0, occluded[2].flow_ml_min = 79.0, now[2].flow_ml_min = 0.0;  // not starved: not target
  const auto t = TargetTerritory::find(open, occluded);
  ASSERT_TRUE(t);
  ASSERT_EQ(t->outlets().size(), 2u);
  EXPECT_NEAR(t->reperfused_fraction(now), 85.0 / 150.0, 1e-12);
  EXPECT_EQ(t->grade(now), Etici::k2b50);
  now[1].flow_ml_min = 50.0;  // (60 + 50) / 150 = 73.3 % -> 2b67
  EXPECT_EQ(t->grade(now), Etici::k2b67);
  now[0].flow_ml_min = 95.0;  // (95 + 50) / 150 = 96.7 % -> 2c
  EXPECT_EQ(t->grade(now), Etici::k2c);
  EXPECT_FALSE(TargetTerritory::find(open, open));
}

}  // namespace
}  // namespace cathbox::flow
