#include "flow/contrast_transport.hpp"

#include <cmath>
#include <algorithm>
#include <deque>
#include <set>

#include <gtest/gtest.h>

#include "flow_test_support.hpp"
#include "vessel/case_generator.hpp"

namespace cathbox::flow {
namespace {

using test::build_or_fail;
using test::load_model;
using test::straight;
using test::y_model;

constexpr double kPi = 3.14159265358979323846;

std::uint32_t segment_named(const vessel::VesselModel& m, const std::string& name) {
  for (std::size_t i = 0; i < m.segments.size(); ++i) {
    if (m.segments[i].name == name) return static_cast<std::uint32_t>(i);
  }
  ADD_FAILURE() << "no segment " << name;
  return 0;
}

CenterlinePosition at_fraction(const ContrastTransport& t, std::uint32_t segment, double fraction) {
  return {segment, fraction * t.locator().length_mm(segment), 0.0};
}

// Checks the iodine balance and the bounds of every cell; returns the relative imbalance.
double check_balance(const ContrastTransport& t, double c0, const std::string& what) {
  const double injected = t.injected_mg();
  const double imbalance = std::abs(injected - t.in_vessels_mg() - t.washed_out_mg());
  EXPECT_EQ(t.stalled_mg(), 0.0) << what;
  for (std::uint32_t s = 0; s < t.network().model().segments.size(); ++s) {
    for (double c : t.cell_concentrations(s)) {
      EXPECT_GE(c, -1e-12) << what;
      EXPECT_LE(c, c0 * (1.0 + 1e-12)) << what;
    }
  }
  return injected > 0.0 ? imbalance / injected : imbalance;
}

TEST(ContrastTransport, MassIsConservedInTheNeuroCases) {
  for (const char* file : {"cases/neuro.hclm", "cases/neuro_aneurysm.hclm", "cases/neuro_stenosis.hclm"}) {
    for (bool pulsatile : {false, true}) {
      FlowSettings s;
      if (pulsatile) {
        s.heart_rate_bpm = 70.0;
        s.pulsatility_index = 1.0;
      }
      const auto net = build_or_fail(load_model(file), s);
      ASSERT_TRUE(net);
      ContrastTransport t(*net);
      const std::uint32_t ica = segment_named(net->model(), "left_internal_carotid");
      ASSERT_EQ(t.inject(at_fraction(t, ica, 0.4), Injection{6.0, 3.0, 300.0}), "");
      double worst = 0.0;
      for (int step = 0; step < 1000; ++step) {  // 10 s
        t.step();
        worst = std::max(worst, check_balance(t, 300.0, file));
      }
      const std::string what = std::string(file) + (pulsatile ? " pulsatile" : "");
      EXPECT_LT(worst, 0.01) << what;   // the bound
      EXPECT_LT(worst, 1e-9) << what;   // what the scheme gives: round-off only
      EXPECT_NEAR(t.injected_mg(), 6.0 * 300.0, 1e-6) << what;
      EXPECT_NEAR(t.injected_volume_ml(), 6.0, 1e-9) << what;
      EXPECT_FALSE(t.injecting()) << what;
      // Washed out within seconds: less than 5 % is left after 10 s (8 s after the injection).
      EXPECT_LT(t.in_vessels_mg(), 0.05 * t.injected_mg()) << what;
    }
  }
}

TEST(ContrastTransport, MassIsConservedOnRandomGraphs) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    for (double dispersion : {0.0, 1.0, 4.0}) {
      FlowSettings s;
      s.dispersion_radii = dispersion;
      const auto net = build_or_fail(vessel::CaseGenerator::random_graph(seed, 1 + static_cast<int>(seed % 4)), s);
      ASSERT_TRUE(net);
      ContrastTransport t(*net);
      const auto seg = static_cast<std::uint32_t>((seed * 7) % net->model().segments.size());
      const std::string err = t.inject(at_fraction(t, seg, 0.5), Injection{0.5, 1.0, 300.0});
      if (!err.empty()) {
        EXPECT_EQ(net->segments()[seg].flow_mm3_s, 0.0) << err;  // only a segment without flow refuses
        continue;
      }
      double worst = 0.0;
      for (int step = 0; step < 300; ++step) {
        t.step();
        worst = std::max(worst, check_balance(t, 300.0, "graph"));
      }
      EXPECT_LT(worst, 1e-9) << "seed " << seed << " dispersion " << dispersion;
      EXPECT_GT(t.injected_mg(), 0.0);
    }
  }
}

// A single straight tube, radius 2 mm, draining 300 mL/min.
std::unique_ptr<FlowNetwork> straight_tube(double length_mm, double dispersion) {
  vessel::VesselModel m;
  m.segments.push_back(straight(1, {0, 0, 0}, {0, 0, length_mm}, 2.0));
  FlowSettings s;
  s.dispersion_radii = dispersion;
  s.outlets = {{1, 300.0, 1}};
  return build_or_fail(m, s);
}

TEST(ContrastTransport, BolusArrivalIsLengthOverVelocity) {
  // A 300 mm tube; a 10 ms bolus at 60 mm, away from the closed inlet (a pulse near a wall
  // that reflects dispersion would drift off it).
  const double length = 300.0;
  for (double dispersion : {0.0, 1.0}) {
    const auto net = straight_tube(length, dispersion);
    ASSERT_TRUE(net);
    const double v = net->segments()[0].mean_velocity_mm_s;
    EXPECT_NEAR(v, 300.0 / 0.06 / (kPi * 4.0), 1e-9);
    ContrastTransport t(*net);
    ASSERT_EQ(t.inject({0, 60.0, 0.0}, Injection{0.01, 1.0, 300.0}), "");
    const double injection_mid = 0.005;
    const std::span<const double> b = t.cell_bounds_mm(0);
    const auto tip = static_cast<std::size_t>(std::upper_bound(b.begin() + 1, b.end() - 1, 60.0) - (b.begin() + 1));
    const double x0 = 0.5 * (b[tip] + b[tip + 1]);  // the injection fills the tip's cell
    // The bolus' centre of mass passes 120, 160 and 200 mm; the washout's mean time at the outlet.
    const double xs[3] = {120.0, 160.0, 200.0};
    double passed[3] = {-1.0, -1.0, -1.0};
    double previous_centre = x0, previous_time = 0.0;
    double washed_t = 0.0, washed_prev = 0.0;
    double peak_c[3] = {0, 0, 0}, peak_t[3] = {0, 0, 0};
    for (int step = 0; step < 200; ++step) {
      t.step();
      const double time = t.time_s();
      const double dm = t.washed_out_mg() - washed_prev;
      washed_prev = t.washed_out_mg();
      washed_t += dm * (time - 0.5 * t.options().step_s);
      const std::span<const double> c = t.cell_concentrations(0);
      double m = 0.0, mx = 0.0;
      for (std::size_t j = 0; j < c.size(); ++j) {
        m += c[j];
        mx += c[j] * 0.5 * (b[j] + b[j + 1]);
      }
      const double centre = m > 0.0 ? mx / m : x0;
      for (int k = 0; k < 3; ++k) {
        if (passed[k] < 0.0 && previous_centre < xs[k] && centre >= xs[k] && t.washed_out_mg() < 1e-3 * t.injected_mg()) {
          passed[k] = previous_time + (time - previous_time) * (xs[k] - previous_centre) / (centre - previous_centre);
        }
        const double ck = t.concentration(0, xs[k]);
        if (ck > peak_c[k]) {
          peak_c[k] = ck;
          peak_t[k] = time;
        }
      }
      previous_centre = centre;
      previous_time = time;
    }
    ASSERT_NEAR(t.washed_out_mg(), t.injected_mg(), 1e-6 * t.injected_mg());
    const double transit = washed_t / t.washed_out_mg() - injection_mid;
    EXPECT_NEAR(transit, (length - x0) / v, 0.01 * (length - x0) / v) << "dispersion " << dispersion;
    for (int k = 0; k < 3; ++k) {
      const double expect = (xs[k] - x0) / v;
      EXPECT_NEAR(passed[k] - injection_mid, expect, 0.01 * expect) << "x " << xs[k] << " dispersion " << dispersion;
      if (dispersion == 0.0) {  // the concentration peak seen at a point, too
        EXPECT_NEAR(peak_t[k] - injection_mid, (xs[k] - x0) / v, 0.03 * (xs[k] - x0) / v + 0.01) << "x " << xs[k];
      }
    }
  }
}

TEST(ContrastTransport, InjectateMixesWithTheLocalFlow) {
  const auto net = straight_tube(100.0, 1.0);
  ASSERT_TRUE(net);
  ContrastTransport t(*net);
  ASSERT_EQ(t.inject({0, 30.0, 0.0}, Injection{50.0, 1.0, 300.0}), "");
  for (int step = 0; step < 300; ++step) t.step();  // 3 s: steady downstream of the tip
  const double q = 1.0, flow = 300.0 / 60.0;
  EXPECT_NEAR(t.concentration(0, 80.0), 300.0 * q / (flow + q), 0.005 * 300.0 * q / (flow + q));
  // Upstream of the tip only dispersion within the segment: far less.
  EXPECT_LT(t.concentration(0, 5.0), 0.01 * t.concentration(0, 80.0));
}

TEST(ContrastTransport, JunctionsSplitContrastByFlow) {
  vessel::VesselModel m = y_model(3.0, 2.0, 2.0, 100, 170);
  FlowSettings s;
  s.dispersion_radii = 0.0;
  s.outlets = {{2, 300.0, 1}, {3, 100.0, 2}};
  const auto net = build_or_fail(m, s);
  ASSERT_TRUE(net);
  ContrastTransport t(*net);
  ASSERT_EQ(t.inject({0, 1.0, 0.0}, Injection{0.02, 1.0, 300.0}), "");
  const auto mass_in = [&](std::uint32_t seg) {
    double sum = 0.0;
    for (double c : t.cell_concentrations(seg)) sum += c;
    return sum;
  };
  bool checked = false;
  for (int step = 0; step < 100 && !checked; ++step) {
    t.step();
    const double total = mass_in(0) + mass_in(1) + mass_in(2);
    if (t.time_s() < 0.1 || mass_in(0) > 1e-5 * total) continue;
    ASSERT_LT(t.washed_out_mg(), 1e-5 * t.injected_mg());  // all of it in the branches
    // Equal cell volumes in both branches (same radius), so cell sums compare masses.
    const double v1 = t.cell_bounds_mm(1).back() / t.cell_concentrations(1).size();
    const double v2 = t.cell_bounds_mm(2).back() / t.cell_concentrations(2).size();
    EXPECT_NEAR((mass_in(1) * v1) / (mass_in(2) * v2), 3.0, 0.01 * 3.0);
    checked = true;
  }
  EXPECT_TRUE(checked);
  // A long injection: both branches carry the parent's concentration.
  ContrastTransport steady(*net);
  ASSERT_EQ(steady.inject({0, 1.0, 0.0}, Injection{20.0, 1.0, 300.0}), "");
  for (int step = 0; step < 400; ++step) steady.step();
  const double c_parent = steady.concentration(0, 55.0);
  EXPECT_NEAR(steady.concentration(1, 150.0), c_parent, 1e-6 * c_parent);
  EXPECT_NEAR(steady.concentration(2, 150.0), c_parent, 1e-6 * c_parent);
}

// Segments downstream of the tip: its own, then every segment blood leaves a reached node by.
std::set<std::uint32_t> receiving_flow(const FlowNetwork& net, std::uint32_t tip) {
  double largest = 0.0;
  for (const SegmentFlow& f : net.segments()) largest = std::max(largest, std::abs(f.flow_mm3_s));
  const auto flowing = [&](double q) { return std::abs(q) > 1e-9 * largest; };
  std::set<std::uint32_t> reached{tip};
  std::deque<int> nodes{net.segments()[tip].flow_mm3_s >= 0.0 ? net.segments()[tip].end_node : net.segments()[tip].start_node};
  std::set<int> seen;
  while (!nodes.empty()) {
    const int n = nodes.front();
    nodes.pop_front();
    if (!seen.insert(n).second) continue;
    for (std::uint32_t s = 0; s < net.segments().size(); ++s) {
      const SegmentFlow& f = net.segments()[s];
      if (f.start_node == n && flowing(f.flow_mm3_s) && f.flow_mm3_s > 0.0) {
        reached.insert(s);
        nodes.push_back(f.end_node);
      }
      if (f.end_node == n && flowing(f.flow_mm3_s) && f.flow_mm3_s < 0.0) {
        reached.insert(s);
        nodes.push_back(f.start_node);
      }
      if (f.start_node == n && net.closed_terminal_of(s) >= 0) reached.insert(s);  // a sac opening here
    }
  }
  return reached;
}

TEST(ContrastTransport, OneCarotidNeverOpacifiesWhatItDoesNotFeed) {
  for (const char* file : {"cases/neuro.hclm", "cases/neuro_aneurysm.hclm", "cases/neuro_stenosis.hclm"}) {
    const auto net = build_or_fail(load_model(file));
    ASSERT_TRUE(net);
    const vessel::VesselModel& m = net->model();
    for (const char* injected : {"right_", "left_"}) {
      const std::string side = injected;
      const std::string other = side == "right_" ? "left_" : "right_";
      const std::uint32_t tip = segment_named(m, side + "internal_carotid");
      const std::set<std::uint32_t> fed = receiving_flow(*net, tip);
      // The territory check is not vacuous: these get nothing from this carotid...
      for (const std::string& name : {other + "internal_carotid", other + "common_carotid", other + "middle_cerebral_m1",
                                      side + "external_carotid", side + "common_carotid", side + "vertebral",
                                      std::string("basilar"), std::string("aortic_arch_1")}) {
        EXPECT_EQ(fed.count(segment_named(m, name)), 0u) << file << " " << side << ": " << name;
      }
      // ...and these do.
      for (const std::string& name : {side + "middle_cerebral_m2_superior", side + "anterior_cerebral_a2",
                                      side + "posterior_communicating"}) {
        EXPECT_EQ(fed.count(segment_named(m, name)), 1u) << file << " " << side << ": " << name;
      }
      ContrastTransport t(*net);
      ASSERT_EQ(t.inject(at_fraction(t, tip, 0.4), Injection{8.0, 4.0, 300.0}), "");
      std::vector<double> peak(m.segments.size(), 0.0);
      for (int step = 0; step < 800; ++step) {
        t.step();
        for (std::uint32_t s = 0; s < m.segments.size(); ++s) peak[s] = std::max(peak[s], t.max_concentration(s));
      }
      for (std::uint32_t s = 0; s < m.segments.size(); ++s) {
        if (fed.count(s) == 0) {
          EXPECT_EQ(peak[s], 0.0) << file << " " << side << ": contrast in " << m.segments[s].name;
        } else if (std::abs(net->segments()[s].flow_ml_min()) > 5.0 || net->closed_terminal_of(s) >= 0) {
          EXPECT_GT(peak[s], 1.0) << file << " " << side << ": no contrast in " << m.segments[s].name;
        }
      }
    }
  }
}

TEST(ContrastTransport, AneurysmSacFillsAndEmptiesSlowly) {
  const auto net = build_or_fail(load_model("cases/neuro_aneurysm.hclm"));
  ASSERT_TRUE(net);
  const std::uint32_t sac = segment_named(net->model(), "right_mca_aneurysm");
  const std::uint32_t m2 = segment_named(net->model(), "right_middle_cerebral_m2_superior");
  ContrastTransport t(*net);
  ASSERT_EQ(t.inject(at_fraction(t, segment_named(net->model(), "right_internal_carotid"), 0.4), Injection{6.0, 3.0, 300.0}), "");
  double sac_peak = 0.0, m2_peak = 0.0;
  int sac_peak_step = 0, m2_peak_step = 0;
  for (int step = 0; step < 800; ++step) {
    t.step();
    if (t.max_concentration(sac) > sac_peak) {
      sac_peak = t.max_concentration(sac);
      sac_peak_step = step;
    }
    if (t.max_concentration(m2) > m2_peak) {
      m2_peak = t.max_concentration(m2);
      m2_peak_step = step;
    }
  }
  EXPECT_GT(sac_peak, 0.1 * m2_peak);
  EXPECT_GT(sac_peak_step, m2_peak_step);              // fills after the branches
  EXPECT_GT(t.max_concentration(sac), t.max_concentration(m2));  // and holds contrast longer
  // Injecting into the sac itself: it empties through its neck into the M2 branches.
  ContrastTransport into(*net);
  ASSERT_EQ(into.inject(at_fraction(into, sac, 0.5), Injection{0.2, 0.5, 300.0}), "");
  for (int step = 0; step < 100; ++step) into.step();
  EXPECT_GT(into.max_concentration(m2), 0.0);
  EXPECT_LT(check_balance(into, 300.0, "sac"), 1e-9);
}

TEST(ContrastTransport, CellsHaveEqualVolumeAndCoverTheSegment) {
  const auto net = build_or_fail(load_model("cases/neuro_stenosis.hclm"));
  ASSERT_TRUE(net);
  ContrastTransport t(*net);
  for (std::uint32_t s = 0; s < net->model().segments.size(); ++s) {
    const std::span<const double> b = t.cell_bounds_mm(s);
    ASSERT_EQ(b.size(), t.cell_concentrations(s).size() + 1);
    EXPECT_EQ(b.front(), 0.0);
    EXPECT_NEAR(b.back(), net->segments()[s].length_mm, 1e-9);
    // Volume of each cell by quadrature of pi r^2 over its arc range.
    const double expected = net->segments()[s].volume_mm3 / static_cast<double>(b.size() - 1);
    for (std::size_t j = 0; j + 1 < b.size(); ++j) {
      ASSERT_LE(b[j], b[j + 1]);
      double vol = 0.0;
      const int n = 64;
      for (int k = 0; k < n; ++k) {
        const double arc = b[j] + (k + 0.5) / n * (b[j + 1] - b[j]);
        const double r = t.locator().radius_at(s, arc);
        vol += kPi * r * r * (b[j + 1] - b[j]) / n;
      }
      EXPECT_NEAR(vol, expected, 2e-3 * expected) << net->model().segments[s].name << " cell " << j;
    }
  }
}

TEST(ContrastTransport, SameInputsSameNumbers) {
  FlowSettings s;
  s.heart_rate_bpm = 65.0;
  s.pulsatility_index = 0.9;
  const auto net = build_or_fail(load_model("cases/neuro.hclm"), s);
  ContrastTransport a(*net), b(*net);
  const std::uint32_t ica = segment_named(net->model(), "right_internal_carotid");
  ASSERT_EQ(a.inject(at_fraction(a, ica, 0.3), Injection{}), "");
  ASSERT_EQ(b.inject(at_fraction(b, ica, 0.3), Injection{}), "");
  for (int step = 0; step < 300; ++step) {
    a.step();
    b.step();
  }
  for (std::uint32_t seg = 0; seg < net->model().segments.size(); ++seg) {
    const auto ca = a.cell_concentrations(seg);
    const auto cb = b.cell_concentrations(seg);
    for (std::size_t j = 0; j < ca.size(); ++j) ASSERT_EQ(ca[j], cb[j]);
  }
  a.reset();
  EXPECT_EQ(a.in_vessels_mg(), 0.0);
  EXPECT_EQ(a.time_s(), 0.0);
}

TEST(ContrastTransport, LocatesTheCatheterTipAndRejectsBadInjections) {
  const auto net = build_or_fail(load_model("cases/neuro.hclm"));
  ContrastTransport t(*net);
  const std::uint32_t ica = segment_named(net->model(), "right_internal_carotid");
  const glm::dvec3 on_axis = t.locator().point_at(ica, 40.0);
  const CenterlinePosition found = t.locate(on_axis + glm::dvec3(0.5, 0.0, 0.0));
  EXPECT_EQ(found.segment, ica);
  EXPECT_NEAR(found.arc_mm, 40.0, 0.6);
  EXPECT_LE(found.distance_mm, 0.5 + 1e-9);
  EXPECT_EQ(t.inject(found, Injection{0.0, 3.0, 300.0}), "injection volume must be in (0, 500] mL");
  EXPECT_EQ(t.inject(found, Injection{6.0, 60.0, 300.0}), "injection rate must be in (0, 50] mL/s");
  EXPECT_EQ(t.inject(found, Injection{6.0, 3.0, -1.0}), "contrast concentration must be in (0, 1000] mgI/mL");
  EXPECT_EQ(t.inject({999, 0.0, 0.0}, Injection{}), "injection site: no segment 999");
  EXPECT_FALSE(t.injecting());
  ASSERT_EQ(t.inject(found, Injection{}), "");
  EXPECT_TRUE(t.injecting());
  t.step();
  t.stop_injection();
  EXPECT_FALSE(t.injecting());
  EXPECT_NEAR(t.injected_volume_ml(), 0.03, 1e-9);  // 10 ms at 3 mL/s
}

}  // namespace
}  // namespace cathbox::flow
