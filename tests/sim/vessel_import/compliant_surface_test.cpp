// The compliant wall on an imported surface (issues 29 and 31): a straight tube, generated, written
// to STL and imported as a user would (`cathbox vessel import tube.stl`), then loaded as a case
// with `surface` and `wall cervical` (no radius: the imported graph's, the distance to the
// surface). The same laws and constants as the wall meshed from centrelines or given as tubes
// (tool/arterial_wall.hpp, compliant_contact.hpp, wall_distension.hpp):
//
// - Laplace: a thin-walled tube under an internal pressure change P distends by
//   dR = P R^2 / (E h) (hoop stress P R / h, hoop strain dR / R); with the carotid's material
//   (E 770 kPa, Riley et al., Stroke 23(7), 1992; h = 0.2 R) a 40 mmHg pulse on R = 2 mm gives
//   69 um. The imported surface, moved in the field the collision queries read, must give it
//   within 10 % all round the lumen.
// - Point load: the tube wall's reference is the ring-load stiffness K = 4 pi R k / beta
//   (Timoshenko & Woinowsky-Krieger 1959, §114; 1,413 mN/mm at R = 2 mm, the upper bound of a
//   point load's by Betti's reciprocity). A guidewire tip pushed sideways into the imported
//   wall presses it by F / K as into the analytic tube of the same radius. The bound, 10 %:
//   K is linear in R at a fixed h / R, and the imported radius is within 5 % of the tube's
//   (surface_import_test's round trip), the faceted wall's plane within its chord sag
//   R (1 - cos(pi / 16)) = 2 % of it.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <span>
#include <vector>
#include <unistd.h>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scenario/case_file.hpp"
#include "scenario/case_wall.hpp"
#include "scenario/case_world.hpp"
#include "tool/arterial_wall.hpp"
#include "tool/compliant_contact.hpp"
#include "tool/simulator.hpp"
#include "tool/tube_network_wall.hpp"
#include "vessel/hclm.hpp"
#include "vessel/mesh_export.hpp"
#include "vessel/vessel_mesher.hpp"
#include "vessel_import/importer.hpp"

namespace cathbox::tool {
namespace {

namespace fs = std::filesystem;

constexpr double kRadius_mm = 2.0;
constexpr double kLength_mm = 60.0;
constexpr double kMmHg_kPa = 0.133322;
constexpr double kRigidPenalty_mN_per_mm = 2e5;  // RodSettings::contact_stiffness_mN_per_mm
const char* const kTools =
    "tool guidewire guidewire\n  section 300 od=0.36 ei=40 gj=31\nend\n";

class CompliantSurface : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("cathbox_compliant_surface_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    vessel::VesselModel tube;
    vessel::Segment s;
    s.id = 1;
    for (double z = 0.0; z <= kLength_mm + 1e-9; z += 2.0) s.points.push_back({glm::dvec3(0.0, 0.0, z), kRadius_mm});
    tube.segments.push_back(s);
    const vessel::VesselSurface surface = vessel::build_vessel_surface(tube);
    ASSERT_TRUE(surface.ok()) << surface.error;
    const std::string stl = (dir_ / "tube.stl").string();
    ASSERT_EQ(vessel::write_mesh(surface.mesh, stl), "");
    const vessel_import::ImportResult imported = vessel_import::import_centerlines(stl);
    ASSERT_TRUE(imported.ok()) << imported.errors.front().to_string();
    ASSERT_TRUE(vessel::save_hclm(imported.model, (dir_ / "tube.hclm").string()).empty());
    ASSERT_EQ(vessel::write_mesh(imported.lumen, (dir_ / "lumen.cbxmesh").string()), "");
    std::printf("imported tube: %s\n", imported.summary().c_str());
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static CaseParse surface_case() {
    return parse_case(std::string("cathbox-case 1\nvessel tube.hclm\nsurface lumen.cbxmesh\nwall cervical\n"
                                  "entry 0 0 4  0 0 1\n") + kTools,
                      (dir_ / "tube.case").string());
  }

  static fs::path dir_;
};
fs::path CompliantSurface::dir_;

TEST_F(CompliantSurface, TheImportedTubeDistendsByLaplacesLawWithinTenPercent) {
  const CaseParse c = surface_case();
  ASSERT_TRUE(c) << c.error().message;
  WorldBuild world = build_world(*c);
  ASSERT_TRUE(world) << world.error().message;
  ASSERT_TRUE((*world)->surface_given());
  const std::unique_ptr<CaseWallField> field = make_case_wall_field(&*c->wall, (*world)->wall(), (*world)->source_model());
  ASSERT_NE(field, nullptr);
  // The radius the graph gives (the distance to the surface) is the tube's.
  EXPECT_NEAR(case_wall_radius_mm(*c->wall, (*world)->source_model()), kRadius_mm, 0.05 * kRadius_mm);

  const ArterialWall wall = arterial_wall(Territory::kCervical);
  const double pressure_kPa = 40.0 * kMmHg_kPa;
  const double laplace_mm = pressure_kPa * kRadius_mm * kRadius_mm / (wall.youngs_modulus_kPa * wall.thickness_ratio * kRadius_mm);
  EXPECT_NEAR(laplace_mm, 0.0693, 0.0005);
  int probed = 0;
  double worst = 0.0;
  for (double z = 15.0; z <= 45.0; z += 5.0) {
    for (int a = 0; a < 12; ++a) {
      const double angle = 2.0 * std::numbers::pi * a / 12.0;
      WallProbe probe;
      probe.center_mm = glm::dvec3(0.8 * std::cos(angle), 0.8 * std::sin(angle), z);
      probe.radius_mm = 0.2;
      probe.range_mm = 5.0;
      WallHint hint;
      WallContact rest, distended;
      field->set_pressure_kPa(0.0);
      ASSERT_TRUE(field->wall().probe(probe, hint, rest));
      field->set_pressure_kPa(pressure_kPa);
      ASSERT_TRUE(field->wall().probe(probe, hint, distended));
      const double moved_mm = distended.distance_mm - rest.distance_mm;
      EXPECT_NEAR(moved_mm, laplace_mm, 0.1 * laplace_mm) << "z " << z << " angle " << a;
      EXPECT_NEAR(glm::length(distended.point_mm - rest.point_mm), moved_mm, 1e-9);  // along the normal
      worst = std::max(worst, std::abs(moved_mm / laplace_mm - 1.0));
      ++probed;
    }
  }
  std::printf("imported tube, 40 mmHg: Laplace %.4f mm; %d probes, worst %.2f %% off\n", laplace_mm, probed, 100.0 * worst);
}

// A guidewire 30 mm in, its tip pushed sideways by each of `loads_mN` in turn (400 steps each):
// the tip's distance from the axis and the wall's whole sideways force on the wire at each.
struct Pressed {
  double stiffness_mN_per_mm = 0.0;  // the contact's
  std::vector<double> tip_off_axis_mm;
  std::vector<double> wall_force_mN;
  double largest_gap_error_mN = 0.0;  // |F - K w| of the contacts (w the contact plane's gap)
};
Pressed press_tip(const WallModel& wall, const Case& c, const vessel::VesselModel* model, std::span<const double> loads_mN) {
  Pressed out;
  Simulator sim(wall, c.tools, *c.entry);
  use_case_wall(sim, &*c.wall, model);
  out.stiffness_mN_per_mm = sim.rod_settings(0).contact_stiffness_mN_per_mm;
  for (int i = 1; i <= 200; ++i) {
    sim.set_insertion(0, std::min(30.0, 0.3 * i));
    sim.step();
  }
  const std::size_t tip = sim.rod(0).node_total() - 1;
  for (const double load_mN : loads_mN) {
    sim.set_node_load(0, tip, glm::dvec3(load_mN, 0.0, 0.0));
    for (int i = 0; i < 400; ++i) sim.step();
    EXPECT_TRUE(sim.rod(0).converged());
    const glm::dvec3 x = sim.rod(0).positions()[tip];
    out.tip_off_axis_mm.push_back(std::hypot(x.x, x.y));
    double sideways_mN = 0.0;
    for (const RodContact& contact : sim.rod(0).contacts()) {
      sideways_mN += contact.normal_force_mN * contact.normal.x;
      const glm::dvec3 p = sim.rod(0).positions()[contact.node];
      const double w = glm::dot(p - contact.point_mm, contact.normal) + sim.rod(0).node_radius_mm(contact.node);
      if (contact.normal_force_mN > 1.0) {
        out.largest_gap_error_mN = std::max(out.largest_gap_error_mN, std::abs(contact.normal_force_mN - out.stiffness_mN_per_mm * w));
      }
    }
    out.wall_force_mN.push_back(sideways_mN);
  }
  return out;
}

TEST_F(CompliantSurface, AToolPressingTheImportedWallMeetsTheTubeWallsStiffness) {
  const CaseParse surface = surface_case();
  ASSERT_TRUE(surface) << surface.error().message;
  WorldBuild world = build_world(*surface);
  ASSERT_TRUE(world) << world.error().message;
  const std::unique_ptr<CaseWallField> field =
      make_case_wall_field(&*surface->wall, (*world)->wall(), (*world)->source_model());
  ASSERT_NE(field, nullptr);
  const CaseParse tube = parse_case(std::string("wall cervical 2\ntube 0  0 0 -2 2  0 0 62 2\nentry 0 0 4  0 0 1\n") + kTools,
                                    "tube.case");
  ASSERT_TRUE(tube) << tube.error().message;
  TubeNetworkWall tube_wall(tube->tubes);
  tube_wall.build();

  const double k_ref = WallShell(arterial_wall(Territory::kCervical), kRadius_mm).ring_load_stiffness_mN_per_mm();
  const double loads_mN[] = {50.0, 200.0};
  const Pressed s = press_tip(field->wall(), *surface, (*world)->source_model(), loads_mN);
  const Pressed t = press_tip(tube_wall, *tube, nullptr, loads_mN);
  EXPECT_EQ(t.stiffness_mN_per_mm, k_ref);
  EXPECT_NEAR(s.stiffness_mN_per_mm, k_ref, 0.05 * k_ref);  // the imported radius within 5 %
  // Each contact gives F = K w, the wall's law (not the rigid wall's 2e5 mN/mm), to the
  // solver's 2 um tolerance on w.
  EXPECT_LT(s.largest_gap_error_mN, 2e-3 * s.stiffness_mN_per_mm + 2.0);
  EXPECT_LT(t.largest_gap_error_mN, 2e-3 * t.stiffness_mN_per_mm + 2.0);
  for (std::size_t i = 0; i < 2; ++i) {
    // The wall holds the load less what the entry's clamp takes, the tube's share.
    EXPECT_NEAR(s.wall_force_mN[i], t.wall_force_mN[i], 0.02 * t.wall_force_mN[i]);
    EXPECT_GT(s.wall_force_mN[i], 0.8 * loads_mN[i]);
  }
  // The tip's give between the two loads: the wall's compliance under the wire, 40-60 um where
  // the rigid wall's penalty would give 1 um. The faceted wall is not the tube: a node rests up
  // to the chord sag (here ~10 um) inside the tube's circle, at each load, and the load shares
  // out over the nodes touching it by that geometry. Bound: 10 % of the tube's give plus twice
  // the sag, measured on the imported lumen.
  double sag_mm = 0.0;
  const vessel::SurfaceMesh& mesh = *(*world)->mesh();
  for (std::size_t k = 0; k < mesh.triangle_count(); ++k) {
    glm::dvec3 c(0.0);
    for (int j = 0; j < 3; ++j) c += glm::dvec3(mesh.positions_mm[mesh.triangles[3 * k + static_cast<std::size_t>(j)]]) / 3.0;
    if (c.z > 10.0 && c.z < 50.0) sag_mm = std::max(sag_mm, kRadius_mm - std::hypot(c.x, c.y));
  }
  const double give_surface = s.tip_off_axis_mm[1] - s.tip_off_axis_mm[0];
  const double give_tube = t.tip_off_axis_mm[1] - t.tip_off_axis_mm[0];
  EXPECT_GT(give_tube, 20.0 * 150.0 / kRigidPenalty_mN_per_mm);
  EXPECT_GT(give_surface, 20.0 * 150.0 / kRigidPenalty_mN_per_mm);
  EXPECT_LT(sag_mm, 0.02);
  EXPECT_NEAR(give_surface, give_tube, 0.1 * give_tube + 2.0 * sag_mm);
  std::printf("faceted wall's sag %.4f mm; wall force %.1f / %.1f mN (surface), %.1f / %.1f (tube)\n", sag_mm,
              s.wall_force_mN[0], s.wall_force_mN[1], t.wall_force_mN[0], t.wall_force_mN[1]);
  std::printf("tip pushed sideways 50 -> 200 mN: imported surface K %.0f mN/mm, gives %.4f mm (off axis %.4f -> %.4f); "
              "tube K %.0f, gives %.4f mm (%.4f -> %.4f)\n",
              s.stiffness_mN_per_mm, give_surface, s.tip_off_axis_mm[0], s.tip_off_axis_mm[1], t.stiffness_mN_per_mm, give_tube,
              t.tip_off_axis_mm[0], t.tip_off_axis_mm[1]);
}

}  // namespace
}  // namespace cathbox::tool
