// The arterial wall's radial mechanics (arterial_wall.hpp) against analytic references, and the
// displaced wall (displaced_wall.hpp) against the exact wall it offsets.
//
// - Laplace: a thin-walled tube under internal pressure P distends by dR = P R^2 / (E h) away
//   from its ends (Laplace's law with Hooke's: hoop stress P R / h, hoop strain dR / R).
// - Ring load: a force P spread round one circumference of a long tube deflects it by
//   w(0) = P beta / (4 pi R k), k = E h / R^2, beta^4 = 3 (1 - nu^2) / (R h)^2, and the
//   deflection decays as e^(-beta x) (cos beta x + sin beta x) (Timoshenko & Woinowsky-Krieger,
//   Theory of Plates and Shells, 2nd ed. 1959, §114, eq. 278; Hetenyi, Beams on Elastic
//   Foundation, 1946).
// - Carotid pulse: a 40 mmHg pulse pressure on the cervical wall gives the circumferential strain
//   that Riley et al. (Stroke 23(7), 1992) measured their modulus from: Y = (R / WT) (PP / CAS),
//   so CAS = PP R / (Y WT) at their Y.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "tool/arterial_wall.hpp"
#include "scenario/case_file.hpp"
#include "scenario/case_wall.hpp"
#include "tool/compliant_contact.hpp"
#include "tool/displaced_wall.hpp"
#include "tool/simulator.hpp"
#include "tool/tube_network_wall.hpp"

namespace cathbox::tool {
namespace {

constexpr double kMmHg_kPa = 0.133322;

TEST(WallShell, UniformPressureDistendsByLaplacesLawWithinTenPercent) {
  for (const Territory t : {Territory::kCervical, Territory::kIntracranial}) {
    const ArterialWall wall = arterial_wall(t);
    for (const double radius_mm : {1.2, 1.55, 2.5, 3.2}) {
      const WallShell shell(wall, radius_mm);
      const double p_kPa = 40.0 * kMmHg_kPa;  // a pulse pressure
      const double spacing_mm = 0.05;
      std::vector<double> load(801, p_kPa);  // 40 mm of vessel, clamped at both ends
      const std::vector<double> w = shell.solve_radial(load, spacing_mm);
      const double laplace_mm = p_kPa * radius_mm * radius_mm / (wall.youngs_modulus_kPa * shell.thickness_mm());
      EXPECT_NEAR(w[400], laplace_mm, 0.1 * laplace_mm) << "R " << radius_mm;
      // (The discretisation and the clamped ends 20 mm away leave it far closer than that.)
      EXPECT_NEAR(w[400], laplace_mm, 1e-6 * laplace_mm) << "R " << radius_mm;
      // The clamped ends hold the wall: no distension there.
      EXPECT_EQ(w.front(), 0.0);
      EXPECT_EQ(w.back(), 0.0);
    }
  }
}

TEST(WallShell, RingLoadDeflectionAndDecayMatchTheLongCylinderSolution) {
  const ArterialWall wall = arterial_wall(Territory::kIntracranial);
  const double radius_mm = 1.55;  // the M1
  const WallShell shell(wall, radius_mm);
  const double spacing_mm = 0.005;
  const std::size_t n = 4001, mid = 2000;  // 20 mm of vessel
  std::vector<double> load(n, 0.0);
  const double force_mN = 10.0;
  load[mid] = force_mN / (2.0 * std::numbers::pi * radius_mm * spacing_mm);
  const std::vector<double> w = shell.solve_radial(load, spacing_mm);
  const double beta = shell.decay_per_mm();
  const double w0_mm = force_mN * beta / (4.0 * std::numbers::pi * radius_mm * shell.hoop_stiffness_kPa_per_mm());
  EXPECT_NEAR(w[mid], w0_mm, 0.1 * w0_mm);
  EXPECT_NEAR(force_mN / w[mid], shell.ring_load_stiffness_mN_per_mm(), 0.1 * shell.ring_load_stiffness_mN_per_mm());
  // The decay: w(x) / w(0) = e^(-beta x) (cos beta x + sin beta x), sampled to two decay lengths.
  for (const double x_mm : {0.1, 0.25, 0.5, 1.0}) {
    const double bx = beta * x_mm;
    const double want = std::exp(-bx) * (std::cos(bx) + std::sin(bx));
    const auto k = static_cast<std::size_t>(std::lround(x_mm / spacing_mm));
    EXPECT_NEAR(w[mid + k] / w[mid], want, 0.02) << "x " << x_mm << " mm";
    EXPECT_NEAR(w[mid - k], w[mid + k], 1e-9 * w0_mm);  // symmetric
  }
  // The shell's own figures for the M1 (README): stiffness to a ring load, decay length.
  std::printf("M1 (R %.2f mm, h %.3f mm, E %.0f kPa): ring-load stiffness %.0f mN/mm, 1/beta %.3f mm, "
              "w(0) %.4f mm under %.0f mN\n",
              radius_mm, shell.thickness_mm(), wall.youngs_modulus_kPa, shell.ring_load_stiffness_mN_per_mm(), 1.0 / beta,
              w[mid], force_mN);
}

TEST(WallShell, CervicalPulseStrainIsTheOneRileysModulusWasMeasuredFrom) {
  // Riley et al. 1992: Y = (R / WT) (PP / CAS). Our wall at their Y, its WT / R, a 40 mmHg pulse:
  // the strain w / R must be CAS = PP R / (Y WT).
  const ArterialWall wall = arterial_wall(Territory::kCervical);
  const WallShell shell(wall, 3.1);
  const double pp_kPa = 40.0 * kMmHg_kPa;
  const std::vector<double> w = shell.solve_radial(std::vector<double>(1001, pp_kPa), 0.05);
  const double cas = pp_kPa / (wall.youngs_modulus_kPa * wall.thickness_ratio);
  EXPECT_NEAR(w[500] / 3.1, cas, 0.1 * cas);
  // A carotid distends by a few percent per pulse (Riley's CAS): 3-6 % here.
  EXPECT_GT(cas, 0.03);
  EXPECT_LT(cas, 0.06);
}

TEST(DisplacedWall, AUniformOffsetOfATubeIsTheWiderTubeExactly) {
  TubeNetworkWall narrow, wide;
  const double w_mm = 0.08;
  // Capsules of one radius each (the offset of a capsule by w is the capsule of radius r + w, and
  // of a union of them the union of the offsets).
  narrow.add_tube(Tube{{0, 0, -10}, {0, 0, 30}, 1.5, 1.5, 0});
  narrow.add_tube(Tube{{0, 0, 30}, {12, 0, 50}, 1.2, 1.2, 1});
  wide.add_tube(Tube{{0, 0, -10}, {0, 0, 30}, 1.5 + w_mm, 1.5 + w_mm, 0});
  wide.add_tube(Tube{{0, 0, 30}, {12, 0, 50}, 1.2 + w_mm, 1.2 + w_mm, 1});
  narrow.build();
  wide.build();
  DisplacedWall displaced(narrow);
  displaced.set_uniform_mm(w_mm);
  int compared = 0;
  for (int i = 0; i < 400; ++i) {
    const double z = -5.0 + 0.11 * i;  // along the straight tube and into the junction
    const double a = 0.37 * i;
    const double r = 1.45 * std::fmod(0.61 * i, 1.0);
    WallProbe p;
    p.center_mm = {r * std::cos(a), r * std::sin(a), z};
    p.radius_mm = 0.18;
    WallHint h1, h2;
    WallContact c1, c2;
    const bool b1 = displaced.probe(p, h1, c1);
    const bool b2 = wide.probe(p, h2, c2);
    ASSERT_EQ(b1, b2) << "z " << z;
    if (!b1) continue;
    EXPECT_EQ(c1.segment, c2.segment);
    EXPECT_NEAR(c1.distance_mm, c2.distance_mm, 1e-9);
    EXPECT_NEAR(glm::length(c1.point_mm - c2.point_mm), 0.0, 1e-9);
    EXPECT_NEAR(glm::length(c1.normal - c2.normal), 0.0, 1e-9);
    ++compared;
  }
  EXPECT_GT(compared, 100);
}

TEST(DisplacedWall, PerSegmentDisplacementMovesOnlyThatSegmentsWall) {
  TubeNetworkWall tubes;
  tubes.add_tube(Tube{{0, 0, -10}, {0, 0, 20}, 1.5, 1.5, 0});
  tubes.add_tube(Tube{{0, 0, 40}, {0, 0, 60}, 1.0, 1.0, 3});
  tubes.build();
  DisplacedWall wall(tubes);
  wall.set_segment_mm(3, 0.05);
  EXPECT_EQ(wall.displacement_mm(0), 0.0);
  EXPECT_EQ(wall.displacement_mm(3), 0.05);
  WallProbe p;
  p.radius_mm = 0.2;
  p.center_mm = {0.9, 0, 5};
  WallHint h;
  WallContact c;
  ASSERT_TRUE(wall.probe(p, h, c));
  EXPECT_NEAR(c.distance_mm, 0.6, 1e-9);
  p.center_mm = {0.6, 0, 50};
  ASSERT_TRUE(wall.probe(p, h, c));
  EXPECT_NEAR(c.distance_mm, 0.45, 1e-9);
  EXPECT_NEAR(c.point_mm.x, 1.05, 1e-9);
  // The pulse: the M1's Laplace distension under 40 mmHg, applied as the field.
  const WallShell m1(arterial_wall(Territory::kIntracranial), 1.0);
  const double dr = 40.0 * kMmHg_kPa * 1.0 / (arterial_wall(Territory::kIntracranial).youngs_modulus_kPa * m1.thickness_mm());
  wall.set_segment_mm(3, dr);
  ASSERT_TRUE(wall.probe(p, h, c));
  EXPECT_NEAR(c.distance_mm, 0.4 + dr, 1e-9);
}

// A case's `wall cervical 2`: every non-coil tool's contact takes the wall's ring-load stiffness
// (1.41 N/mm for the carotid's material at 2 mm, not the rigid wall's 2e5 mN/mm) and the tissue's
// shear under its patch as friction's stick spring, and the
// guidewire pushed 20 mm into a dead end presses the wall by F / K within the bounded layer
// (25 % of the radius), and past it by the tenfold stiffer recruited wall's law, at its
// converged steps; never past the solver's hard limit (two layers).
TEST(CompliantContact, AWallLineGivesTheWallsStiffnessAndItsBoundedLayer) {
  const CaseParse c = parse_case("wall cervical 2\ntube 0  0 0 -10 2  0 0 60 2\nentry 0 0 0  0 0 1\n"
                                 "tool guidewire guidewire\n  section 300 od=0.36 ei=40 gj=31\nend\n",
                                 "w.case");
  ASSERT_TRUE(c) << c.error().message;
  ASSERT_TRUE(c->wall.has_value());
  const WallShell shell(arterial_wall(Territory::kCervical), 2.0);
  const double k = shell.ring_load_stiffness_mN_per_mm();
  EXPECT_NEAR(k, 1413.0, 5.0);
  TubeNetworkWall wall(c->tubes);
  wall.build();
  Simulator sim(wall, c->tools, *c->entry);
  use_case_wall(sim, &*c->wall);
  EXPECT_EQ(sim.rod_settings(0).contact_stiffness_mN_per_mm, k);
  EXPECT_NEAR(sim.rod_settings(0).wall_layer_mm, 0.5, 1e-9);  // 25 % of 2 mm
  EXPECT_EQ(sim.rod_settings(0).wall_stiffening, kCollagenStiffening);
  EXPECT_NEAR(sim.rod_settings(0).max_penetration_ratio * 0.18, 1.0, 1e-9);  // two layers
  // Friction's stick spring: Mindlin's 8 G a / (2 - nu) of the same tissue (770 kPa, nu 0.5).
  EXPECT_NEAR(sim.rod_settings(0).wall_shear_mN_per_mm2, 8.0 * (770.0 / 3.0) / 1.5, 1e-9);
  double largest_mN = 0.0;
  int checked = 0;
  int past_layer = 0;
  int converged_steps = 0;
  for (int i = 1; i <= 3000; ++i) {
    sim.set_insertion(0, std::min(80.0, 0.03 * i));  // 30 mm/s, 20 mm past the end at 62 mm
    sim.step();
    if (!sim.rod(0).converged()) continue;
    ++converged_steps;
    for (const RodContact& contact : sim.rod(0).contacts()) {
      const glm::dvec3 x = sim.rod(0).positions()[contact.node];
      const double r = sim.rod(0).node_radius_mm(contact.node);
      // In the tube's straight part the exact penetration (the wall's curvature round the node:
      // the solver's gap follows it), at the cap the contact plane's.
      const double pressed_mm = x.z < 58.0 ? r + std::hypot(x.x, x.y) - 2.0 : glm::dot(x - contact.point_mm, contact.normal) + r;
      EXPECT_LE(pressed_mm, 1.0 + 1e-6);
      if (contact.normal_force_mN > 1.0) {
        // The wall's own stiffness: F = K w within the layer, K (0.5 + 10 (w - 0.5)) past it (to
        // the solver's 2 um tolerance on w).
        const double expected_mN = pressed_mm <= 0.5 ? k * pressed_mm : k * (0.5 + kCollagenStiffening * (pressed_mm - 0.5));
        const double slope = pressed_mm <= 0.5 ? k : k * kCollagenStiffening;
        EXPECT_NEAR(contact.normal_force_mN, expected_mN, slope * 2e-3 + 1e-3 * contact.normal_force_mN) << "step " << i;
        ++checked;
        if (pressed_mm > 0.5) ++past_layer;
      }
      largest_mN = std::max(largest_mN, contact.normal_force_mN);
    }
  }
  // The steps that press the wall converge: 6,633 contacts over 1 mN on converged steps (2,505 of
  // 3,000 steps); with one flat plane per node (no curved gap) 29 (2,083 steps).
  EXPECT_GT(checked, 1000);
  std::printf("compliant dead end: %d of 3000 steps converged; largest contact %.1f mN, %d of %d contacts past the layer\n",
              converged_steps, largest_mN, past_layer, checked);
}

TEST(CompliantContact, TheCaseLineIsCheckedWithOneLine) {
  const char* const bad[] = {"wall arterial 2\n", "wall cervical 0.2\n", "wall cervical\n",
                             "wall cervical 2\nwall cervical 2\n", "wall intracranial x\n"};
  for (const char* text : bad) {
    const CaseParse c = parse_case(text, "w.case");
    ASSERT_FALSE(c) << text;
    EXPECT_EQ(c.error().message.find("w.case:"), 0u) << c.error().message;
    EXPECT_EQ(c.error().message.find('\n'), std::string::npos) << c.error().message;
  }
  const CaseParse ok = parse_case("wall intracranial 1.55\ntube 0 0 0 0 1 0 0 9 1\nentry 0 0 1 0 0 1\n", "w.case");
  ASSERT_TRUE(ok) << ok.error().message;
  EXPECT_EQ(ok->wall->territory, Territory::kIntracranial);
  EXPECT_EQ(ok->wall->radius_mm, 1.55);
  const CaseParse rigid = parse_case("tube 0 0 0 0 1 0 0 9 1\nentry 0 0 1 0 0 1\n", "w.case");
  ASSERT_TRUE(rigid) << rigid.error().message;
  EXPECT_FALSE(rigid->wall.has_value());
}

}  // namespace
}  // namespace cathbox::tool
