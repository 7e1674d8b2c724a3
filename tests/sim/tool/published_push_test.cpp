// The push force of a 0.014" guidewire, alone and inside a microcatheter, tracked through a
// tortuous 20 cm tube like an intracranial carotid path, against a published bench measurement
// (issue 29, item 3; docs/sim-tool/published-forces.md).
//
// Source (abstract read, AJNR 19:1571-1576, 1998): Zoarski GH, Mathis JM, Hebel JR,
// *Performance characteristics of microcatheter systems in a standardized tortuous pathway*.
// A 20 cm long three-dimensional pathway "simulating the intracranial carotid circulation",
// 0.065" (1.65 mm) inner diameter PTFE tubing in a 37 C water bath, an Instron load frame with a
// 2 lb load cell; a 0.014" stainless steel noncoated guidewire, its tip 1 cm beyond the catheter's.
// "Trackability testing of the guidewire alone established reproducible performance with maximum
// load forces of less than 8 g. Maximum gram forces for the four reinforced [hydrophilic]
// microcatheters were not greatly different, measuring between 9 and 14 g."
//
// What the abstract does not give, and what is taken here instead (each a choice, named):
// - the pathway's bends: a siphon-like path of 450 degrees in four bends of 5-10 mm radius in
//   three planes (below), 200 mm long;
// - the push rate: 5 mm/s (the forces here are friction and bending, nearly rate-free: the
//   water's drag on 200 mm of wire at 5 mm/s is 0.01 mN; the real-time solver's drag floor
//   adds ~10 mN, the last test);
// - the wire's stiffness: the bundled 0.014" microwire's (cases/neuro_coiling.case) with its tip
//   straight; its wall coefficient the case's 0.08, and PTFE on steel's 0.16 (Wypych 2018,
//   Table 11.1, dry: the upper bound for a wetted bare wire); the bundled hydrophilic
//   microcatheter keeps its 0.1;
// - no haemostatic valve (a load frame pushing into tubing); its default 20 mN is left out.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scenario/case_file.hpp"
#include "tool/simulator.hpp"
#include "tool/tube_network_wall.hpp"

namespace cathbox::tool {
namespace {

constexpr double kGramForce_mN = 9.80665;
constexpr double kWireAloneMax_mN = 8.0 * kGramForce_mN;       // Zoarski 1998: < 8 g
constexpr double kSystemMin_mN = 9.0 * kGramForce_mN;          // Zoarski 1998: 9-14 g
constexpr double kSystemMax_mN = 14.0 * kGramForce_mN;
constexpr double kTubeRadius_mm = 0.065 * 25.4 / 2.0;          // 0.825 mm
constexpr double kWaterAt37C_mPa_s = 0.69;
constexpr double kPtfeOnSteelDynamic = 0.16;                   // Wypych 2018, Table 11.1 (dry)

// A path drawn as a turtle: straight runs and circular bends, each bend turning in a plane
// rolled about the current tangent (3D).
class Path {
 public:
  Path() { points_.push_back(p_); }
  Path& straight(double length_mm) {
    p_ += t_ * length_mm;
    points_.push_back(p_);
    length_mm_ += length_mm;
    return *this;
  }
  Path& bend(double angle_deg, double radius_mm, double roll_deg) {
    const double roll = roll_deg * M_PI / 180.0;
    const glm::dvec3 b = glm::cross(t_, n_);
    const glm::dvec3 n = n_ * std::cos(roll) + b * std::sin(roll);
    const glm::dvec3 t0 = t_;
    const glm::dvec3 p0 = p_;
    const double angle = angle_deg * M_PI / 180.0;
    const int steps = std::max(2, static_cast<int>(std::ceil(angle_deg)));
    for (int i = 1; i <= steps; ++i) {
      const double a = angle * i / steps;
      p_ = p0 + radius_mm * std::sin(a) * t0 + radius_mm * (1.0 - std::cos(a)) * n;
      points_.push_back(p_);
    }
    t_ = std::cos(angle) * t0 + std::sin(angle) * n;
    n_ = -std::sin(angle) * t0 + std::cos(angle) * n;
    length_mm_ += angle * radius_mm;
    return *this;
  }
  [[nodiscard]] const std::vector<glm::dvec3>& points() const { return points_; }
  [[nodiscard]] double length_mm() const { return length_mm_; }

 private:
  glm::dvec3 p_{0, 0, 0};
  glm::dvec3 t_{0, 0, 1};
  glm::dvec3 n_{1, 0, 0};
  double length_mm_ = 0.0;
  std::vector<glm::dvec3> points_;
};

// 200 mm: a cervical run, the petrous turn, the ascent, the siphon's genu and the turn to the
// terminal segment, 450 degrees in all.
constexpr double kPathLength_mm = 200.0;
TubeNetworkWall carotid_like_tube() {
  Path path;
  path.straight(40.0)
      .bend(90.0, 10.0, 0.0)   // petrous: 15.7 mm
      .straight(15.0)
      .bend(90.0, 8.0, 90.0)   // ascent, another plane: 12.6 mm
      .straight(10.0)
      .bend(180.0, 5.0, 90.0)  // the siphon's genu: 15.7 mm
      .straight(10.0)
      .bend(90.0, 6.0, 60.0);  // supraclinoid: 9.4 mm
  path.straight(kPathLength_mm - path.length_mm());
  TubeNetworkWall wall;
  wall.add_polyline(path.points(), kTubeRadius_mm, 0);
  wall.build();
  return wall;
}

// The default 0.014" wire (the bundled coiling case's microwire has the same stiffness
// sections, 40 / 3 / 0.3 N.mm2 over 1750 / 35 / 15 mm), its tip straight.
ToolSpec microwire(double friction) {
  ToolSpec w = default_guidewire();
  w.name = "microwire";
  for (ToolSection& s : w.sections) s.curve_deg = 0.0;
  w.friction = friction;
  w.blood_viscosity_mPa_s = kWaterAt37C_mPa_s;
  w.valve_friction_mN = 0.0;
  return w;
}

// The bundled microcatheter (cases/neuro_coiling.case), its tip straight.
ToolSpec microcatheter() {
  ToolSpec c = default_microcatheter();  // its name, kind and wall friction (0.1)
  c.sections = {ToolSection{1350.0, 0.8, 8.0, 6.0, 0.0}, ToolSection{120.0, 0.75, 3.0, 2.4, 0.0},
                ToolSection{30.0, 0.7, 1.0, 0.8, 0.0}};
  c.inner_diameter_mm = 0.43;
  c.blood_viscosity_mPa_s = kWaterAt37C_mPa_s;
  c.valve_friction_mN = 0.0;
  c.max_spacing_mm = 2.0;
  c.tip_spacing_mm = 0.5;
  c.tip_zone_mm = 40.0;
  return c;
}

struct Push {
  double max_mN = 0.0;     // largest force at the hand (all tools pushed together)
  double mean_mN = 0.0;    // over the last half of the push
  double unconverged = 0;  // share of steps some tool did not converge
};

// Pushes every tool by `to_mm` at `speed` mm/s (1 ms ticks), the last tool `lead_mm` ahead of the
// first, and records the summed hand force of the tools pushed.
Push push_through(Simulator& sim, double lead_mm, double to_mm, double speed_mm_s) {
  Push out;
  const double per_step = speed_mm_s * 1e-3;
  const std::size_t last = sim.tool_count() - 1;
  int steps = 0;
  int unconverged = 0;
  int counted = 0;
  for (double ins = 0.0; ins < to_mm; ins += per_step) {
    sim.set_insertion(0, ins);
    if (last > 0) sim.set_insertion(last, ins + lead_mm);
    sim.step();
    double sum = 0.0;
    bool converged = true;
    for (std::size_t t = 0; t <= last; ++t) {
      sum += sim.hand_force_mN(t);
      converged = converged && sim.rod(t).converged();
    }
    ++steps;
    unconverged += converged ? 0 : 1;
    out.max_mN = std::max(out.max_mN, sum);
    if (ins > 0.5 * to_mm) {
      out.mean_mN += sum;
      ++counted;
    }
  }
  out.mean_mN /= std::max(1, counted);
  out.unconverged = static_cast<double>(unconverged) / std::max(1, steps);
  return out;
}

constexpr double kSpeed_mm_s = 5.0;
constexpr double kPushedTo_mm = kPathLength_mm - 12.0;  // the leading tip 2 mm short of the end

// The bundled microwire with its soft 50 mm stretched to `soft_mm` at 3 N.mm2 (a longer taper).
// The one published length found for it: a guidewire's core "tapers toward a distal section
// measuring 35-40 cm" behind a proximal ~145 cm (*Interventional Cardiology*, Wiley, ISBN
// 9781119697381, the guidewire section near its Fig. 5.7-5.8; coronary guidewires; editors
// not read). No published EI along a neurovascular wire or microcatheter was found
// (docs/sim-tool/published-forces.md lists the searches), so the soft section keeps the bundled
// 3 N.mm2: only its length is sourced.
constexpr double kPublishedDistalTaper_mm = 350.0;  // the lower end of 35-40 cm
ToolSpec microwire_soft_for(double soft_mm, double friction) {
  ToolSpec w = microwire(friction);
  w.sections[0].length_mm -= soft_mm - 35.0;
  w.sections[1].length_mm = soft_mm;
  return w;
}

// NOT YET (DISABLED_): Zoarski 1998's guidewire alone reads under 8 g (78.5 mN) through its
// 20 cm pathway. The simulator's wire through the carotid-like path above, pushed to 198 mm:
// the bundled microwire 1,496 mN at its wall mu 0.08 (19x), 2,860 mN at PTFE on steel's 0.16;
// with its soft 3 N.mm2 stretched over the published 35 cm distal taper (no 40 N.mm2 shaft in
// the path) 107 mN at 0.08 (1.4x; 250 mm read the same). The rise is the mechanics, not the solver
// (FrictionlessPushIntoABendCostsTheBendingEnergyOfTheStiffPart below): pushing the 40 N.mm2
// shaft into the siphon's 5 mm genu costs (40 - 3) / (2 x 5^2) = 0.74 N with no friction at
// all (8 g in any bend under 15.4 mm), and friction on the bend's contact forces adds to it.
// So either the path above is tighter than Zoarski's (its radii are not in the abstract) or the
// bundled wire's 50 mm soft tip is short of a real 0.014" wire's 35-40 cm taper; with the
// taper's length sourced but not its stiffness, the wire still reads over 8 g: its 3 N.mm2
// entering the genu alone costs 3 / (2 x 5^2) = 60 mN before friction. Run:
// --gtest_also_run_disabled_tests.
TEST(PublishedPush, DISABLED_NotYetGuidewireAloneThroughACarotidLikePathwayStaysUnderZoarskisEightGrams) {
  const TubeNetworkWall wall = carotid_like_tube();
  struct Wire {
    ToolSpec spec;
    const char* what;
  };
  const std::vector<Wire> wires{{microwire(0.08), "bundled microwire, mu 0.08"},
                                {microwire(kPtfeOnSteelDynamic), "bundled microwire, mu 0.16"},
                                {microwire_soft_for(kPublishedDistalTaper_mm, 0.08), "soft 350 mm, mu 0.08"}};
  for (const Wire& w : wires) {
    const std::vector<ToolSpec> tools{w.spec};
    Simulator sim(wall, tools, Entry{{0, 0, 0}, {0, 0, 1}});
    const Push push = push_through(sim, 0.0, kPushedTo_mm + 10.0, kSpeed_mm_s);
    std::printf("guidewire alone, %s: largest %.1f mN (%.2f g), mean over the last half %.1f mN; "
                "unconverged %.2f %% (published: < 8 g = %.1f mN)\n",
                w.what, push.max_mN, push.max_mN / kGramForce_mN, push.mean_mN, 100.0 * push.unconverged,
                kWireAloneMax_mN);
    EXPECT_LT(push.max_mN, kWireAloneMax_mN) << w.what;
  }
}

// NOT YET (DISABLED_): Zoarski 1998's microcatheter systems (the wire 1 cm beyond the tip,
// pushed together) read 9-14 g (88-137 mN) at most. The bundled microcatheter over the bundled
// microwire (mu 0.16) through the path above: 1,726 mN (13x the upper bound), for the reason
// the test above gives (the wire's 40 N.mm2 shaft inside it, in the genu).
TEST(PublishedPush, DISABLED_NotYetMicrocatheterOverTheWireIsWithinZoarskisNineToFourteenGrams) {
  const TubeNetworkWall wall = carotid_like_tube();
  ToolSpec w = microwire(kPtfeOnSteelDynamic);
  w.inside = "microcatheter";
  const std::vector<ToolSpec> tools{microcatheter(), w};
  Simulator sim(wall, tools, Entry{{0, 0, 0}, {0, 0, 1}});
  const Push system = push_through(sim, 10.0, kPushedTo_mm, kSpeed_mm_s);
  std::printf("microcatheter over the wire: largest %.1f mN (%.2f g), mean over the last half %.1f mN; "
              "unconverged %.2f %% (published: 9-14 g = %.1f-%.1f mN)\n",
              system.max_mN, system.max_mN / kGramForce_mN, system.mean_mN, 100.0 * system.unconverged,
              kSystemMin_mN, kSystemMax_mN);
  EXPECT_GE(system.max_mN, kSystemMin_mN);
  EXPECT_LE(system.max_mN, kSystemMax_mN);
}

struct BendPush {
  double before_mN = 0.0;   // the step 5 mm short of the bend (the soft tip entering it)
  double in_bend_mN = 0.0;  // mean while the step crosses the bend's middle third
};

// A wire of 60 mm at 3 N.mm2 on a 40 N.mm2 shaft, frictionless and without drag, pushed at
// 10 mm/s through a 180 degree bend of radius R in the 0.825 mm tube.
BendPush push_stiffness_step_through_a_bend(double R, const RodSettings& settings) {
  Path path;
  path.straight(10.0).bend(180.0, R, 0.0);
  path.straight(120.0);
  TubeNetworkWall wall;
  wall.add_polyline(path.points(), kTubeRadius_mm, 0);
  wall.build();
  ToolSpec w = microwire_soft_for(60.0, 0.0);
  w.sections.resize(2);  // 60 mm at 3 N.mm2 on the 40 N.mm2 shaft
  w.drag_mN_s_per_mm2 = 0.0;
  const std::vector<ToolSpec> tools{w};
  Simulator sim(wall, tools, Entry{{0, 0, 0}, {0, 0, 1}}, settings);
  const double arc = M_PI * R;
  BendPush out;
  int count = 0;
  for (double ins = 0.0; ins < 60.0 + 10.0 + 2.0 * arc / 3.0; ins += 0.01) {
    sim.set_insertion(0, ins);
    sim.step();
    const double step_at = ins - 60.0;  // the stiffness step's distance along the path
    if (std::abs(step_at - 5.0) < 0.005) out.before_mN = sim.hand_force_mN(0);
    if (step_at > 10.0 + arc / 3.0) {
      out.in_bend_mN += sim.hand_force_mN(0);
      ++count;
    }
  }
  out.in_bend_mN /= std::max(1, count);
  return out;
}

// Why the wire above reads what it reads (the analytic solution, energy): with no friction, no
// valve and no drag, a wire stores EI kappa^2 / 2 per mm in a bend, so while its stiffness step
// (EI_soft -> EI_stiff) crosses a bend of radius R the hand pushes with
// (EI_stiff - EI_soft) / (2 R_w^2), R_w the radius the wire's axis takes: between R - c and
// R + c, c the clearance (tube radius less the wire's); the tip's soft part entering the bend
// costs EI_soft / (2 R_w^2). Solved to convergence (quasi-static settings) it holds within 5 %;
// the real-time settings a session runs read more (printed: 63.5 against 50.5 mN converged,
// +26 %, at 10 mm/s in a 20 mm bend), which is not what parts the wire above from Zoarski.
TEST(PublishedPush, FrictionlessPushIntoABendCostsTheBendingEnergyOfTheStiffPart) {
  const double R = 20.0;
  RodSettings converged;
  converged.newton_iterations = 20;
  converged.convergence_mm = 1e-7;
  converged.min_drag_mN_s_per_mm2 = 1e-5;
  converged.buckling_seed_mm = 0.0;
  const BendPush push = push_stiffness_step_through_a_bend(R, converged);
  const BendPush real_time = push_stiffness_step_through_a_bend(R, RodSettings{});
  const double c = kTubeRadius_mm - 0.18;
  const auto energy = [&](double d_ei, double r) { return 1e3 * d_ei / (2.0 * r * r); };
  std::printf("frictionless, stiffness step 3 -> 40 N.mm2 in a %.0f mm bend: %.1f mN converged, %.1f real-time "
              "(energy: %.1f-%.1f); the soft tip entering it %.2f mN (%.2f real-time; energy %.2f-%.2f)\n",
              R, push.in_bend_mN, real_time.in_bend_mN, energy(37.0, R + c), energy(37.0, R - c), push.before_mN,
              real_time.before_mN, energy(3.0, R + c), energy(3.0, R - c));
  EXPECT_GE(push.in_bend_mN, 0.95 * energy(37.0, R + c));
  EXPECT_LE(push.in_bend_mN, 1.05 * energy(37.0, R - c));
  EXPECT_GE(push.before_mN, 0.95 * energy(3.0, R + c));
  EXPECT_LE(push.before_mN, 1.05 * energy(3.0, R - c));
}

}  // namespace
}  // namespace cathbox::tool

