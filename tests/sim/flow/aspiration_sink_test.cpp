// An aspiration catheter's open tip as a sink in the flow network: its flow against Poiseuille's
// law through the catheter's lumen and the node pressure (an analytic series circuit), against
// the published aspiration flows (Nikoubashman et al., AJNR 2018;39:905-911), and fragments
// following the flow into it (flow/embolus.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "flow/aspiration.hpp"
#include "flow/embolus.hpp"
#include "flow_test_support.hpp"

namespace cathbox::flow {
namespace {

using test::build_or_fail;
using test::link;
using test::straight;
using test::y_model;

constexpr double kPa_per_mmHg = 133.322387415;
constexpr double kInch_mm = 25.4;

// 50 mm of r 1.5 then 50 mm of r 1.5 (a node between them), 200 mL/min in, one outlet.
vessel::VesselModel tube_in_two() {
  vessel::VesselModel m;
  m.segments.push_back(straight(1, {0, 0, 0}, {0, 0, 50}, 1.5));
  m.segments.push_back(straight(2, {0, 0, 50}, {0, 0, 100}, 1.5));
  link(m, 1, 2);
  return m;
}

FlowSettings tube_settings() {
  FlowSettings s;
  s.calibrate_terminals = false;
  s.outlets = {{2, 200.0, 1}};
  s.inflows = {{1, 200.0, 2}};
  return s;
}

// The catheter's lumen is 128 mu L / (pi D^4); the sink at the middle node draws
// (p1 - p_vac) / R_c where KCL gives p1 = (Q_in + p_vac / R_c) / (1 / (R_B + R_t) + 1 / R_c).
TEST(AspirationSink, DrawsThePoiseuilleFlowOfTheCatheterFromItsNode) {
  const vessel::VesselModel m = tube_in_two();
  const FlowSettings set = tube_settings();
  auto net = build_or_fail(m, set);
  ASSERT_TRUE(net);
  const double mu = set.viscosity_mPa_s * 1e-3;
  // A 0.068" catheter, 1320 mm long, on the pump (Froehler 2017: -25.6 inHg).
  const double d_mm = 0.068 * kInch_mm;
  const double r_c = 128.0 * mu * 1320.0 / (std::numbers::pi * std::pow(d_mm, 4));
  EXPECT_NEAR(catheter_resistance_Pa_s_per_mm3(1320.0, d_mm, set.viscosity_mPa_s), r_c, 1e-12 * r_c);
  const double q_in = 200.0 / 0.06;
  const double r_b = 8.0 * mu * 50.0 / (std::numbers::pi * std::pow(1.5, 4));
  const double r_t = net->terminals()[1].role == EndRole::kOutlet ? net->terminals()[1].resistance_Pa_s_per_mm3
                                                                  : net->terminals()[0].resistance_Pa_s_per_mm3;
  const double p_vac = vacuum_Pa(VacuumSource::kPump) - set.venous_pressure_mmHg * kPa_per_mmHg;  // above venous
  const AspirationSink sink{0, 49.0, vacuum_Pa(VacuumSource::kPump), r_c};  // 1 mm before the node
  ASSERT_TRUE(net->occlude({}, {}, std::span(&sink, 1)));
  ASSERT_EQ(net->sinks().size(), 1u);
  EXPECT_EQ(net->sink_node(0), net->segments()[0].end_node) << "the nearer end of its segment";
  const double p1 = (q_in + p_vac / r_c) / (1.0 / (r_b + r_t) + 1.0 / r_c);
  const double q_sink = (p1 - p_vac) / r_c;
  std::printf("sink %.1f mL/min (analytic %.1f); outlet %.1f of 200 mL/min\n", net->sink_flow_ml_min(0), 0.06 * q_sink,
              net->segments()[1].flow_ml_min());
  EXPECT_NEAR(net->sink_flow_ml_min(0), 0.06 * q_sink, 1e-6 * 0.06 * q_sink);
  EXPECT_NEAR(net->segments()[0].flow_mm3_s, q_in, 1e-6 * q_in) << "the inflow stays as prescribed";
  EXPECT_NEAR(net->segments()[1].flow_mm3_s, q_in - q_sink, 1e-6 * q_in) << "the outlet gets what the catheter leaves";
  // None restores the network without a sink.
  ASSERT_TRUE(net->occlude({}));
  EXPECT_TRUE(net->sinks().empty());
  EXPECT_NEAR(net->segments()[1].flow_mm3_s, q_in, 1e-6 * q_in);
  // Bad sinks: one line, nothing changed.
  const AspirationSink bad{7, 0.0, -1.0, r_c};
  EXPECT_FALSE(net->occlude({}, {}, std::span(&bad, 1)));
  const AspirationSink no_lumen{0, 0.0, -1.0, 0.0};
  EXPECT_FALSE(net->occlude({}, {}, std::span(&no_lumen, 1)));
  EXPECT_TRUE(net->sinks().empty());
}

// Nikoubashman et al. (AJNR 2018;39:905-911) measured aspiration flows in vitro (water/glycerol,
// 3.7 mPa s, the tip at atmospheric pressure) and concluded that a 60 mL syringe (-90 kPa) on a
// modern distal aspiration catheter (ACE 64: 0.064", 132 cm) draws enough to reverse the flow of
// an MCA, while the Pump MAX is unlikely to reverse ICA or MCA flow without balloon protection.
// The tip in a bath at 0 gauge: Q = |vacuum| / R_c (Froehler 2017's vacuums), against the MCA's
// flow (Zarrinkoob et al. 2015: ~21/33 of an ICA's ~270 mL/min, ~170 mL/min; the bundled left
// MCA outlets: 171.8 mL/min) and an ICA's (~270 mL/min).
TEST(AspirationSink, FreeFlowsMatchThePublishedReversalOfMcaFlow) {
  const double r_ace64 = catheter_resistance_Pa_s_per_mm3(1320.0, 0.064 * kInch_mm, 3.7);
  const double syringe_ml_min = 0.06 * -vacuum_Pa(VacuumSource::kSyringe60) / r_ace64;
  const double pump_ml_min = 0.06 * -vacuum_Pa(VacuumSource::kPump) / r_ace64;
  const double r_068 = catheter_resistance_Pa_s_per_mm3(1320.0, 0.068 * kInch_mm, 3.5);
  const double r_035 = catheter_resistance_Pa_s_per_mm3(1500.0, 0.035 * kInch_mm, 3.5);
  std::printf("ACE 64 (3.7 mPa s): syringe %.0f, pump %.0f mL/min; 0.068\" in blood on the pump %.0f, 0.035\" %.0f mL/min\n",
              syringe_ml_min, pump_ml_min, 0.06 * -vacuum_Pa(VacuumSource::kPump) / r_068,
              0.06 * -vacuum_Pa(VacuumSource::kPump) / r_035);
  EXPECT_GT(syringe_ml_min, 171.8) << "reverses an MCA's flow";
  EXPECT_LT(syringe_ml_min, 270.0) << "not an ICA's without protection";
  EXPECT_LT(pump_ml_min, 270.0);
  // Hundreds of mL/min for the large-bore catheters, tens for a 0.035" one (R ~ 1/D^4).
  EXPECT_GT(0.06 * -vacuum_Pa(VacuumSource::kPump) / r_068, 200.0);
  EXPECT_LT(0.06 * -vacuum_Pa(VacuumSource::kPump) / r_035, 30.0);
}

// Parent r 1.5 into two r 1.2 branches, 250 mL/min in; the catheter's tip at the junction.
vessel::VesselModel y_tube() {
  return y_model(1.5, 1.2, 1.2, 24, 32);
}

// A fragment from the parent follows the flow into the catheter when its sink draws more than
// either branch takes; released at the tip's node, straight in. A 0.035" catheter draws a few
// tens of mL/min: the fragment goes on into a branch and lodges beyond.
TEST(AspirationSink, AFragmentFollowsTheFlowIntoTheCatheter) {
  const vessel::VesselModel m = y_tube();
  FlowSettings set;
  set.calibrate_terminals = false;
  set.outlets = {{2, 150.0, 1}, {3, 100.0, 2}};
  set.inflows = {{1, 250.0, 3}};
  auto net = build_or_fail(m, set);
  ASSERT_TRUE(net);
  const Fragment f{{0, 10.0, 0.0}, 1.0, 2.0, {}};
  const auto sink_of = [](double id_mm, double length_mm) {
    return AspirationSink{0, 59.0, vacuum_Pa(VacuumSource::kPump), catheter_resistance_Pa_s_per_mm3(length_mm, id_mm, 3.5)};
  };
  const AspirationSink strong = sink_of(0.068 * kInch_mm, 1320.0);
  ASSERT_TRUE(net->occlude({}, {}, std::span(&strong, 1)));
  std::printf("0.068\": sink %.0f mL/min, branches %.0f / %.0f\n", net->sink_flow_ml_min(0), net->segments()[1].flow_ml_min(),
              net->segments()[2].flow_ml_min());
  ASSERT_GT(net->sink_flow_ml_min(0), std::max(net->segments()[1].flow_ml_min(), net->segments()[2].flow_ml_min()));
  auto t = EmbolusTransit::start(*net, f);
  ASSERT_TRUE(t);
  EXPECT_EQ(t->advance(*net, 1.0), TransitState::kAspirated);
  EXPECT_TRUE(t->path().aspirated);
  EXPECT_NEAR(t->travelled_mm(), 50.0, 1e-6) << "to the node, then in";
  auto at_tip = EmbolusTransit::start(*net, Fragment{{0, 60.0, 0.0}, 1.0, 2.0, {}});
  ASSERT_TRUE(at_tip);
  EXPECT_EQ(at_tip->state(), TransitState::kAspirated) << "released at the node: at once";
  EXPECT_FALSE(carry_fragment(*net, f)) << "no lodging: one line";
  const AspirationSink weak = sink_of(0.035 * kInch_mm, 1500.0);
  ASSERT_TRUE(net->occlude({}, {}, std::span(&weak, 1)));
  auto on = EmbolusTransit::start(*net, f);
  ASSERT_TRUE(on);
  on->advance(*net, 10.0);
  EXPECT_EQ(on->state(), TransitState::kAtOutlet);
  EXPECT_FALSE(on->path().aspirated);
}

}  // namespace
}  // namespace cathbox::flow
