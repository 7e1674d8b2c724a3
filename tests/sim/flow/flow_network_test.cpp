#include "flow/flow_network.hpp"

#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "flow/territory.hpp"
#include "flow_test_support.hpp"
#include "vessel/case_generator.hpp"

namespace cathbox::flow {
namespace {

using test::build_or_fail;
using test::kirchhoff_residual;
using test::link;
using test::load_model;
using test::straight;

constexpr double kPi = 3.14159265358979323846;

double segment_flow(const FlowNetwork& net, const std::string& name) {
  for (std::size_t i = 0; i < net.model().segments.size(); ++i) {
    if (net.model().segments[i].name == name) return net.segments()[i].flow_ml_min();
  }
  ADD_FAILURE() << "no segment " << name;
  return 0.0;
}

void expect_balanced(const FlowNetwork& net, const std::string& what) {
  EXPECT_LT(kirchhoff_residual(net), 1e-10) << what;
  double in = 0.0, out = 0.0;
  for (const Terminal& t : net.terminals()) {
    if (t.role == EndRole::kInlet) in += t.flow_ml_min;
    if (t.role == EndRole::kOutlet) {
      out += t.flow_ml_min;
      EXPECT_GT(t.flow_ml_min, 0.0) << what << ": outlet of segment " << t.segment << " drains nothing";
    }
    if (t.role == EndRole::kClosed) {
      EXPECT_EQ(t.flow_ml_min, 0.0) << what;
    }
  }
  EXPECT_NEAR(in, out, 1e-9 * std::max(1.0, in)) << what;
}

TEST(FlowNetwork, KirchhoffOnEveryBundledCase) {
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::source_path("cases"))) {
    const std::string path = entry.path().string();
    vessel::VesselModel model;
    FlowSettings settings;
    if (entry.path().extension() == ".hclm") {
      model = load_model("cases/" + entry.path().filename().string());
    } else if (entry.path().extension() == ".case") {
      const tool::CaseParse c = tool::load_case(path);
      ASSERT_TRUE(c) << c.error().message;
      model = load_model("cases/" + std::filesystem::path(c->vessel_path).filename().string());
      settings = c->flow;
    } else {
      continue;
    }
    ++files;
    for (bool calibrated : {true, false}) {
      settings.calibrate_terminals = calibrated;
      const auto net = build_or_fail(model, settings);
      ASSERT_TRUE(net) << path;
      expect_balanced(*net, path);
      EXPECT_GT(net->total_inflow_ml_min(), 0.0) << path;
    }
  }
  EXPECT_GE(files, 9);
}

TEST(FlowNetwork, KirchhoffOnRandomTreesAndGraphs) {
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    vessel::RandomTreeOptions options;
    options.segments = 20 + static_cast<int>(seed) * 10;
    const auto tree = build_or_fail(vessel::CaseGenerator::random_tree(seed, options));
    ASSERT_TRUE(tree);
    expect_balanced(*tree, "tree " + std::to_string(seed));
    for (int cycles = 1; cycles <= 6; ++cycles) {
      const vessel::VesselModel g = vessel::CaseGenerator::random_graph(seed, cycles);
      for (bool calibrated : {true, false}) {
        FlowSettings s;
        s.calibrate_terminals = calibrated;
        const auto net = build_or_fail(g, s);
        ASSERT_TRUE(net);
        const std::string what = "graph " + std::to_string(seed) + "/" + std::to_string(cycles);
        expect_balanced(*net, what);
        EXPECT_GT(net->total_inflow_ml_min(), 0.0) << what;
        // Flow runs downhill: from the higher to the lower pressure end of every segment.
        for (const SegmentFlow& f : net->segments()) {
          const double dp = net->node_pressure_Pa(f.start_node) - net->node_pressure_Pa(f.end_node);
          EXPECT_NEAR(f.flow_mm3_s * f.resistance_Pa_s_per_mm3, dp, 1e-9 * (1.0 + std::abs(dp))) << what;
        }
      }
    }
  }
}

// Poiseuille resistance by numerical quadrature (Simpson), independent of the closed form.
double quadrature_resistance(const vessel::Segment& s, double mu_Pa_s) {
  double r_total = 0.0;
  for (std::size_t i = 1; i < s.points.size(); ++i) {
    const double len = glm::length(s.points[i].pos_mm - s.points[i - 1].pos_mm);
    const double r0 = s.points[i - 1].radius_mm, r1 = s.points[i].radius_mm;
    const int n = 200;
    double sum = 0.0;
    for (int k = 0; k <= n; ++k) {
      const double r = r0 + (r1 - r0) * k / n;
      const double w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
      sum += w * 8.0 * mu_Pa_s / (kPi * r * r * r * r);
    }
    r_total += sum * len / n / 3.0;
  }
  return r_total;
}

TEST(FlowNetwork, AnalyticBifurcationSplit) {
  // Parent 60 mm of r 3, a tapered child (r 2 -> 1.6) and a thin child (r 1.5), fixed terminal
  // resistances from targets of 200 and 80 mL/min, 300 mL/min in.
  vessel::VesselModel m;
  m.segments.push_back(straight(1, {0, 0, 0}, {0, 0, 60}, 3.0));
  m.segments.push_back(straight(2, {0, 0, 60}, {20, 0, 100}, 2.0, 1.6));
  m.segments.push_back(straight(3, {0, 0, 60}, {-15, 0, 90}, 1.5));
  link(m, 1, 2);
  link(m, 1, 3);
  FlowSettings s;
  s.calibrate_terminals = false;
  s.outlets = {{2, 200.0, 1}, {3, 80.0, 2}};
  s.inflows = {{1, 300.0, 3}};
  const auto net = build_or_fail(m, s);
  ASSERT_TRUE(net);
  const double mu = 3.5e-3;
  const double drop = (93.0 - 5.0) * 133.322387415;
  double g[2];
  for (int i = 0; i < 2; ++i) {
    const double r_seg = quadrature_resistance(m.segments[static_cast<std::size_t>(i) + 1], mu);
    EXPECT_NEAR(net->segments()[static_cast<std::size_t>(i) + 1].resistance_Pa_s_per_mm3, r_seg, 1e-8 * r_seg);
    const double r_t = drop / ((i == 0 ? 200.0 : 80.0) / 0.06);
    g[i] = 1.0 / (r_seg + r_t);
  }
  const double q_in = 300.0;
  EXPECT_NEAR(net->segments()[1].flow_ml_min(), q_in * g[0] / (g[0] + g[1]), 1e-9 * q_in);
  EXPECT_NEAR(net->segments()[2].flow_ml_min(), q_in * g[1] / (g[0] + g[1]), 1e-9 * q_in);
  EXPECT_NEAR(net->segments()[0].flow_ml_min(), q_in, 1e-9 * q_in);
  // The parent's pressure drop is its flow times its resistance.
  const SegmentFlow& parent = net->segments()[0];
  EXPECT_NEAR(net->node_pressure_Pa(parent.start_node) - net->node_pressure_Pa(parent.end_node),
              parent.flow_mm3_s * quadrature_resistance(m.segments[0], mu), 1e-8);
  // Mean velocity of a cylinder: Q / (pi r^2).
  EXPECT_NEAR(net->segments()[2].mean_velocity_mm_s, net->segments()[2].flow_mm3_s / (kPi * 1.5 * 1.5), 1e-9);
}

TEST(FlowNetwork, CalibratedOutletsDrainTheirTargetsAtArterialPressure) {
  const auto net = build_or_fail(load_model("cases/neuro.hclm"));
  ASSERT_TRUE(net);
  for (const Terminal& t : net->terminals()) {
    if (t.role == EndRole::kOutlet) {
      EXPECT_NEAR(t.flow_ml_min, t.target_ml_min, 1e-9 * t.target_ml_min);
    }
    if (t.role == EndRole::kInlet) {
      EXPECT_NEAR(net->node_pressure_mmHg(t.node), 93.0, 1e-9);
    }
  }
  EXPECT_NEAR(net->total_inflow_ml_min(), 5000.0, 1e-6);
}

TEST(FlowNetwork, NeuroFlowsMatchTheLiterature) {
  // With the default (calibrated) terminals; fixed ones give each territory a few % less.
  const FlowSettings defaults;
  {
    const auto net = build_or_fail(load_model("cases/neuro.hclm"), defaults);
    ASSERT_TRUE(net);
    double cerebral = 0.0, carotid = 0.0;
    for (const char* side : {"right_", "left_"}) {
      const double ica = segment_flow(*net, std::string(side) + "internal_carotid");
      const double va = segment_flow(*net, std::string(side) + "vertebral");
      const double cca = segment_flow(*net, std::string(side) + "common_carotid");
      EXPECT_NEAR(ica, internal_carotid_flow_ml_min(defaults), 0.10 * internal_carotid_flow_ml_min(defaults)) << side;
      EXPECT_NEAR(va, vertebral_flow_ml_min(defaults), 0.25 * vertebral_flow_ml_min(defaults)) << side;
      EXPECT_NEAR(cca, common_carotid_flow_ml_min(defaults), 0.10 * common_carotid_flow_ml_min(defaults)) << side;
      cerebral += ica + va;
      carotid += ica;
    }
    EXPECT_NEAR(cerebral, 750.0, 0.05 * 750.0);  // 15 % of 5 L/min
    EXPECT_GT(carotid / cerebral, 0.65);          // 72 % in [2]
    EXPECT_LT(carotid / cerebral, 0.80);
    EXPECT_NEAR(net->total_inflow_ml_min(), 5000.0, 1e-6);
    // Poiseuille's law needs laminar flow: the mean Reynolds number stays below 2300 everywhere.
    for (const SegmentFlow& f : net->segments()) EXPECT_LT(f.reynolds, 2300.0);
  }
}

TEST(FlowNetwork, StenosisSendsCollateralFlowThroughTheCircleOfWillis) {
  const auto healthy = build_or_fail(load_model("cases/neuro.hclm"));
  const auto stenosed = build_or_fail(load_model("cases/neuro_stenosis.hclm"));
  ASSERT_TRUE(healthy && stenosed);
  const double left = segment_flow(*stenosed, "left_internal_carotid");
  const double right = segment_flow(*stenosed, "right_internal_carotid");
  EXPECT_LT(left, 0.92 * right);
  EXPECT_LT(left, segment_flow(*healthy, "left_internal_carotid"));
  // The anterior communicating artery runs from the left A1 to the right A2: negative flow is
  // right to left, towards the starved side; in the healthy case it carries almost nothing.
  EXPECT_LT(segment_flow(*stenosed, "anterior_communicating"), -10.0);
  EXPECT_LT(std::abs(segment_flow(*healthy, "anterior_communicating")), 5.0);
  // The stenosis is the fastest place in the left ICA.
  for (std::size_t i = 0; i < stenosed->model().segments.size(); ++i) {
    if (stenosed->model().segments[i].name == "left_internal_carotid") {
      EXPECT_GT(stenosed->segments()[i].peak_velocity_mm_s, 4.0 * stenosed->segments()[i].mean_velocity_mm_s);
    }
  }
}

TEST(FlowNetwork, AneurysmSacIsClosed) {
  const auto net = build_or_fail(load_model("cases/neuro_aneurysm.hclm"));
  ASSERT_TRUE(net);
  int closed = 0;
  for (const Terminal& t : net->terminals()) {
    if (t.role != EndRole::kClosed) continue;
    ++closed;
    EXPECT_EQ(net->model().segments[t.segment].name, "right_mca_aneurysm");
    EXPECT_NEAR(net->segments()[t.segment].flow_mm3_s, 0.0, 1e-9);
    EXPECT_EQ(net->closed_terminal_of(t.segment), static_cast<int>(&t - net->terminals().data()));
  }
  EXPECT_EQ(closed, 1);
  expect_balanced(*net, "aneurysm");
}

TEST(FlowNetwork, CaseOverridesTakeEffect) {
  const vessel::VesselModel model = load_model("cases/neuro.hclm");
  FlowSettings s;
  s.outlets = {{16, 150.0, 7}};      // right M2 superior
  s.closed = {{17, 0.1, 8}};         // right M2 inferior occluded
  s.viscosity_mPa_s = 4.0;
  const auto net = build_or_fail(model, s);
  ASSERT_TRUE(net);
  EXPECT_NEAR(segment_flow(*net, "right_middle_cerebral_m2_superior"), 150.0, 1e-6);
  EXPECT_NEAR(segment_flow(*net, "right_middle_cerebral_m2_inferior"), 0.0, 1e-9);
  expect_balanced(*net, "overrides");
  // Viscosity scales every Poiseuille resistance.
  const auto base = build_or_fail(model);
  EXPECT_NEAR(net->segments()[0].resistance_Pa_s_per_mm3, base->segments()[0].resistance_Pa_s_per_mm3 * 4.0 / 3.5, 1e-12);
  // A prescribed inflow other than the outlets' total scales the drains.
  FlowSettings more;
  more.inflows = {{1, 6000.0, 3}};
  const auto scaled = build_or_fail(model, more);
  EXPECT_NEAR(scaled->total_inflow_ml_min(), 6000.0, 1e-6);
  expect_balanced(*scaled, "inflow 6000");
}

struct BadOverride {
  const char* text;
  const char* error;
};
class FlowOverrideErrors : public ::testing::TestWithParam<BadOverride> {};

TEST_P(FlowOverrideErrors, NameTheCaseLine) {
  const tool::CaseParse c = tool::parse_case(GetParam().text, "x.case");
  ASSERT_TRUE(c) << c.error().message;
  const FlowBuild b = FlowNetwork::build(load_model("cases/neuro.hclm"), c->flow);
  ASSERT_FALSE(b);
  EXPECT_EQ(b.error().message, GetParam().error);
}

INSTANTIATE_TEST_SUITE_P(
    Bad, FlowOverrideErrors,
    ::testing::Values(
        BadOverride{"vessel n.hclm\n\nflow outlet 999 100\n", "x.case:3: flow outlet: no segment 999 in the vessel model"},
        BadOverride{"vessel n.hclm\nflow outlet 13 100\n", "x.case:2: flow outlet: segment 13's distal end is not a free end"},
        BadOverride{"vessel n.hclm\nflow inflow 4 100\n", "x.case:2: flow inflow: segment 4's proximal end is not a free end"},
        BadOverride{"vessel n.hclm\nflow closed 5\n", "x.case:2: flow closed: segment 5's distal end is not a free end"}));

TEST(FlowNetwork, InflowWithoutOutletIsAnError) {
  vessel::VesselModel m;
  m.segments.push_back(straight(1, {0, 0, 0}, {0, 0, 30}, 2.0));
  FlowSettings s;
  s.closed = {{1, 0.1, 4}};
  s.inflows = {{1, 100.0, 5}};
  const FlowBuild b = FlowNetwork::build(m, s);
  ASSERT_FALSE(b);
  EXPECT_EQ(b.error().message, "flow: segment 1 has an inflow but its network has no outlet");
  // Without a prescribed inflow the sealed vessel simply has no flow.
  s.inflows.clear();
  const auto still = build_or_fail(m, s);
  ASSERT_TRUE(still);
  EXPECT_EQ(still->segments()[0].flow_mm3_s, 0.0);
}

TEST(FlowNetwork, RootsShareTheInflowAndARootlessLoopTakesItsWidestEnd) {
  // Two roots meeting at a confluence (as the vertebrals at the basilar) share the inflow.
  vessel::VesselModel m;
  m.segments.push_back(straight(1, {0, 0, 40}, {0, 0, 0}, 2.5));  // ends at the origin
  m.segments.push_back(straight(2, {30, 0, 0}, {0, 0, 0}, 1.5));  // ends at the origin too
  m.segments.push_back(straight(3, {0, 0, 0}, {0, 30, 0}, 2.0));
  link(m, 1, 3);
  link(m, 2, 3);
  const auto two_roots = build_or_fail(m);
  ASSERT_TRUE(two_roots);
  expect_balanced(*two_roots, "two roots");
  int inlets = 0;
  for (const Terminal& t : two_roots->terminals()) inlets += t.role == EndRole::kInlet;
  EXPECT_EQ(inlets, 2);
  // A loop whose segments all run one way round, with outward branches only: no free start.
  vessel::VesselModel ring;
  ring.segments.push_back(straight(1, {0, 0, 0}, {30, 0, 0}, 1.5));
  ring.segments.push_back(straight(2, {30, 0, 0}, {15, 26, 0}, 1.5));
  ring.segments.push_back(straight(3, {15, 26, 0}, {0, 0, 0}, 1.5));
  ring.segments.push_back(straight(4, {30, 0, 0}, {60, 0, 0}, 2.0));
  ring.segments.push_back(straight(5, {15, 26, 0}, {15, 56, 0}, 1.2));
  link(ring, 1, 2);
  link(ring, 2, 3);
  link(ring, 3, 1);
  link(ring, 1, 4);
  link(ring, 2, 5);
  const auto net = build_or_fail(ring);
  ASSERT_TRUE(net);
  expect_balanced(*net, "ring");
  int ring_inlets = 0;
  for (const Terminal& t : net->terminals()) {
    if (t.role != EndRole::kInlet) continue;
    ++ring_inlets;
    EXPECT_EQ(net->model().segments[t.segment].id, 4);  // the widest free end
  }
  EXPECT_EQ(ring_inlets, 1);
  EXPECT_GT(net->total_inflow_ml_min(), 0.0);
}

TEST(FlowNetwork, PulsatilityAveragesToTheSteadyFlow) {
  FlowSettings s;
  s.heart_rate_bpm = 72.0;
  s.pulsatility_index = 1.2;
  const auto net = build_or_fail(load_model("cases/y_bifurcation.hclm"), s);
  ASSERT_TRUE(net);
  const double period = 60.0 / 72.0;
  double sum = 0.0, lo = 1e9, hi = 0.0;
  const int n = 1000;
  for (int i = 0; i < n; ++i) {
    const double w = net->flow_scale(period * i / n);
    sum += w;
    lo = std::min(lo, w);
    hi = std::max(hi, w);
  }
  EXPECT_NEAR(sum / n, 1.0, 1e-9);
  EXPECT_NEAR(hi - lo, 1.2, 1e-3);  // (max - min) / mean = the pulsatility index
  EXPECT_NEAR(net->max_flow_scale(), 1.6, 1e-12);
  EXPECT_NEAR(net->flow_scale(0.3), net->flow_scale(0.3 + period), 1e-9);
}

TEST(FlowNetwork, BadSettingsAreErrors) {
  const vessel::VesselModel m = load_model("cases/y_bifurcation.hclm");
  FlowSettings s;
  s.viscosity_mPa_s = 0.0;
  EXPECT_EQ(FlowNetwork::build(m, s).error().message, "flow: viscosity must be > 0");
  s = {};
  s.venous_pressure_mmHg = 100.0;
  EXPECT_FALSE(FlowNetwork::build(m, s));
  s = {};
  s.pulsatility_index = 3.0;
  EXPECT_FALSE(FlowNetwork::build(m, s));
}

TEST(FlowNetwork, SameInputSameNumbers) {
  const vessel::VesselModel m = load_model("cases/neuro_stenosis.hclm");
  const auto a = build_or_fail(m);
  const auto b = build_or_fail(m);
  for (std::size_t i = 0; i < m.segments.size(); ++i) EXPECT_EQ(a->segments()[i].flow_mm3_s, b->segments()[i].flow_mm3_s);
}

}  // namespace
}  // namespace cathbox::flow
