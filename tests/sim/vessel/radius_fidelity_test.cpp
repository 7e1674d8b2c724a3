// The surface follows the INPUT centreline's radius (issue 17, "real geometry stays true"):
// smoothing does not shrink circles, stenosis throats and bulges come out at their input radius,
// narrow-angle junctions do not pinch the branches, and along curved, helical, confluent and
// looping segments the lumen stays within 3 % of the input radius. Every figure is measured by
// cutting the surface with planes normal to the input centreline (radius_probe.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "radius_probe.hpp"
#include "vessel/case_generator.hpp"
#include "vessel/centerline_smoother.hpp"
#include "vessel/hclm.hpp"
#include "vessel/mesh_analysis.hpp"
#include "vessel_test_support.hpp"

namespace cathbox::vessel {
namespace {

constexpr double kPi = 3.14159265358979323846;

// One straight segment along z, 60 mm, points every `spacing_mm`, radius profile r(z).
template <class Profile>
VesselModel straight(double spacing_mm, Profile radius) {
  VesselModel model;
  Segment s;
  s.id = 1;
  const int n = static_cast<int>(std::round(60.0 / spacing_mm));
  for (int i = 0; i <= n; ++i) {
    const double z = 60.0 * i / n;
    s.points.push_back({{0.0, 0.0, z}, radius(z)});
  }
  model.segments.push_back(std::move(s));
  return model;
}

// The mean radius of the surface cut by the plane z = z0 (a straight segment along z).
double surface_radius_at(const SurfaceMesh& mesh, double z0, double reach) {
  const test::Cut cut = test::cut_surface(mesh, {0.0, 0.0, z0}, {0.0, 0.0, 1.0}, reach);
  EXPECT_TRUE(cut.closed());
  return cut.mean;
}

TEST(RadiusFidelity, TaubinSmoothingKeepsCirclesRound) {
  // A 300 degree arc of a circle of radius R, sampled every R/5 .. R/40: after the default
  // smoothing every point is within 0.5 % of R from the centre (end points are fixed).
  for (double radius : {2.0, 13.5, 40.0}) {
    for (double per_radius : {5.0, 10.0, 40.0}) {
      std::vector<CenterlinePoint> arc;
      const int n = static_cast<int>(std::round(300.0 / 180.0 * kPi * per_radius));
      for (int i = 0; i <= n; ++i) {
        const double a = (300.0 / 180.0 * kPi) * i / n;
        arc.push_back({{radius * std::cos(a), radius * std::sin(a), 0.0}, 1.0});
      }
      for (int pass = 0; pass < MeshOptions{}.smoothing_passes; ++pass) taubin_polyline(arc);
      double worst = 0.0;
      for (const CenterlinePoint& p : arc) worst = std::max(worst, std::abs(glm::length(p.pos_mm) / radius - 1.0));
      EXPECT_LT(worst, 0.005) << "R " << radius << " spacing R/" << per_radius;
    }
  }
  // The thesis' (1,2,1) filter (three passes) moves a 13.5 mm arc sampled every mm inward by
  // ~0.05-0.07 mm, 5 % of a 1.2 mm lumen; the default keeps it within 0.01 mm.
  std::vector<CenterlinePoint> arc;
  for (int i = 0; i <= 60; ++i) {
    const double a = i / 13.5;
    arc.push_back({{13.5 * std::cos(a), 13.5 * std::sin(a), 0.0}, 1.0});
  }
  std::vector<CenterlinePoint> taubin = arc;
  for (int pass = 0; pass < 3; ++pass) {
    smooth_polyline(arc);
    taubin_polyline(taubin);
  }
  EXPECT_GT(13.5 - glm::length(arc[30].pos_mm), 0.045);
  EXPECT_LT(std::abs(13.5 - glm::length(taubin[30].pos_mm)), 0.01);
}

TEST(RadiusFidelity, TaubinSmoothingRemovesPointToPointNoise) {
  std::vector<CenterlinePoint> p;
  for (int i = 0; i < 40; ++i) p.push_back({{0.2 * i, (i % 2 == 0 ? 0.05 : -0.05), 0.0}, i % 2 == 0 ? 1.05 : 0.95});
  for (int pass = 0; pass < 3; ++pass) taubin_polyline(p);
  for (std::size_t i = 3; i + 3 < p.size(); ++i) {
    EXPECT_LT(std::abs(p[i].pos_mm.y), 0.005) << i;
    EXPECT_NEAR(p[i].radius_mm, 1.0, 0.005) << i;  // points 0.2 radii apart: the radius is smoothed too
  }
}

TEST(RadiusFidelity, StenosisThroatsComeOutAtTheirInputRadius) {
  // Gaussian stenoses of 30-90 % of a 2 mm radius, 4 mm half-width, sampled densely and
  // sparsely (0.5 .. 2 mm between points): the throat within 5 % of its input radius.
  for (double reduction : {0.3, 0.5, 0.7, 0.9}) {
    for (double spacing : {0.5, 1.0, 1.5, 2.0}) {
      const VesselModel model = straight(spacing, [&](double z) {
        const double x = (z - 30.0) / 4.0;
        return 2.0 * (1.0 - reduction * std::exp(-x * x));
      });
      const VesselSurface surface = build_vessel_surface(model);
      ASSERT_TRUE(surface.ok()) << surface.error;
      const double throat = 2.0 * (1.0 - reduction);
      const double got = surface_radius_at(surface.mesh, 30.0, 3.0);
      std::printf("stenosis %.0f %%, points every %.1f mm: throat %+.2f %%\n", 100.0 * reduction, spacing,
                  100.0 * (got / throat - 1.0));
      EXPECT_NEAR(got / throat, 1.0, 0.05) << reduction * 100 << " % stenosis, points every " << spacing << " mm: "
                                           << got << " mm for " << throat;
    }
  }
}

TEST(RadiusFidelity, BundledSeventyPercentStenosisStaysSeventyPercent) {
  // cases/neuro_stenosis.hclm, left ICA: 0.853 mm at the throat in the file (was 1.04 mm on the
  // surface, a 64 % stenosis, with the (1,2,1) filter and per-point rings).
  const HclmReadResult read = load_hclm(test::case_path("neuro_stenosis"));
  ASSERT_TRUE(read.ok());
  const VesselSurface surface = build_vessel_surface(read.model);
  ASSERT_TRUE(surface.ok()) << surface.error;
  const Segment* ica = nullptr;
  for (const Segment& s : read.model.segments) {
    if (s.name == "left_internal_carotid") ica = &s;
  }
  ASSERT_NE(ica, nullptr);
  const std::vector<test::AxisSample> axis = test::input_axis(*ica);
  std::size_t throat = 0;
  for (std::size_t i = 0; i < axis.size(); ++i) {
    if (axis[i].radius < axis[throat].radius) throat = i;
  }
  const test::Cut cut = test::cut_surface(surface.mesh, axis[throat].pos, axis[throat].tangent, 2.0 * axis[throat].radius);
  ASSERT_TRUE(cut.closed());
  std::printf("neuro_stenosis ICA throat: %+.2f %%\n", 100.0 * (cut.mean / axis[throat].radius - 1.0));
  EXPECT_NEAR(cut.mean / axis[throat].radius, 1.0, 0.05) << cut.mean << " mm at the throat for " << axis[throat].radius;
}

TEST(RadiusFidelity, BulgesFollowTheInputAlongTheirWholeLength) {
  // A 1.6 mm vessel widening to 2.5 mm and back over 8 mm (a raised cosine), sampled every
  // 0.4 .. 3 mm: the surface radius within 5 % of the input all along (was -29 % at the peak).
  for (double spacing : {0.4, 1.0, 2.0, 3.0}) {
    const VesselModel model = straight(spacing, [](double z) {
      const double x = (z - 30.0) / 4.0;
      return std::abs(x) < 1.0 ? 1.6 + 0.9 * 0.5 * (1.0 + std::cos(kPi * x)) : 1.6;
    });
    const VesselSurface surface = build_vessel_surface(model);
    ASSERT_TRUE(surface.ok()) << surface.error;
    const test::ProfileError e = test::profile_error(surface.mesh, model.segments[0], 10.0, 50.0);
    std::printf("bulge, points every %.1f mm: worst %+.2f %% over %d cuts\n", spacing, 100.0 * e.worst, e.samples);
    EXPECT_GT(e.samples, 100);
    EXPECT_LT(std::abs(e.worst), 0.05) << "points every " << spacing << " mm: " << e.worst_surface << " for "
                                       << e.worst_input << " at " << e.worst_arc << " mm";
    EXPECT_NEAR(surface_radius_at(surface.mesh, 30.0, 4.0) / 2.5, 1.0, 0.05) << "peak, points every " << spacing;
  }
}

// Two branches of radius r_branch `angle_deg` apart meeting a trunk of radius r_trunk at the
// origin: a confluence (branches flow in) or a bifurcation (they flow out), 40 mm each.
VesselModel narrow_junction(double angle_deg, bool confluence, double r_branch, double r_trunk) {
  VesselModel model;
  const double half = angle_deg * kPi / 360.0;
  Segment trunk;
  trunk.id = 3;
  for (int i = 0; i <= 30; ++i) {
    const double z = confluence ? 40.0 * i / 30.0 : -40.0 + 40.0 * i / 30.0;
    trunk.points.push_back({{0.0, 0.0, z}, r_trunk});
  }
  for (int b = 0; b < 2; ++b) {
    Segment s;
    s.id = b + 1;
    const glm::dvec3 dir(b == 0 ? std::sin(half) : -std::sin(half), 0.0, std::cos(half));
    for (int i = 0; i <= 30; ++i) {
      const double t = confluence ? -40.0 * (30 - i) / 30.0 : 40.0 * i / 30.0;
      s.points.push_back({t * dir, r_branch});
    }
    (confluence ? s.children : s.parents).push_back(3);
    (confluence ? trunk.parents : trunk.children).push_back(s.id);
    model.segments.push_back(std::move(s));
  }
  model.segments.push_back(std::move(trunk));
  return model;
}

TEST(RadiusFidelity, NarrowJunctionsDoNotPinchTheBranches) {
  // The vertebral arteries into the basilar (r 1.6 -> 1.65 mm) at 15-25 degrees, as a confluence
  // and the mirror bifurcation: beyond 1.5 radii from the junction centre, the lumen on each
  // branch's outer side (away from the other branch) within 3 % of the input radius. Before the
  // junction fit one branch came out ~6 % narrow and the other ~5 % wide at 18 degrees.
  for (const bool confluence : {true, false}) {
    for (double angle : {15.0, 18.0, 20.0, 25.0}) {
      for (int m : {8, 16}) {
        const VesselModel model = narrow_junction(angle, confluence, 1.6, 1.65);
        ASSERT_TRUE(validate_model(model).empty());
        MeshOptions options;
        options.ring_points = m;
        const VesselSurface surface = build_vessel_surface(model, options);
        test::expect_valid_surface(surface, model);
        if (HasFatalFailure()) return;
        EXPECT_EQ(count_self_intersections(surface.mesh), 0u);
        for (int b = 0; b < 2; ++b) {
          const Segment& branch = model.segments[static_cast<std::size_t>(b)];
          const Segment& other = model.segments[static_cast<std::size_t>(1 - b)];
          const glm::dvec3 other_dir =
              glm::normalize(confluence ? other.points.front().pos_mm : other.points.back().pos_mm);
          double worst = 0.0;
          double worst_at = 0.0;
          int samples = 0;
          for (const test::AxisSample& a : test::input_axis(branch)) {
            const double from_centre = glm::length(a.pos);
            if (from_centre < 1.5 * 1.6 || from_centre > 30.0) continue;
            const glm::dvec3 away = glm::normalize(a.pos - from_centre * other_dir);
            const test::Cut cut = test::cut_surface(surface.mesh, a.pos, a.tangent, 2.0 * 1.6,
                                                    [&](const glm::dvec3& d) { return glm::dot(d, away) > 0.0; });
            ++samples;
            const double e = cut.mean / 1.6 - 1.0;
            if (std::abs(e) > std::abs(worst)) {
              worst = e;
              worst_at = from_centre;
            }
          }
          std::printf("%s %.0f deg, M %d, branch %d: outer side worst %+.2f %% over %d cuts\n",
                      confluence ? "confluence" : "bifurcation", angle, m, b, 100.0 * worst, samples);
          EXPECT_GT(samples, 50);
          EXPECT_LT(std::abs(worst), 0.03) << (confluence ? "confluence " : "bifurcation ") << angle << " deg, M " << m
                                           << ", branch " << b << ": " << worst * 100 << " % at " << worst_at
                                           << " mm from the centre";
        }
      }
    }
  }
}

TEST(RadiusFidelity, CurvedHelicalConfluentAndLoopingSegmentsWithinThreePercentOfTheInput) {
  std::vector<std::pair<std::string, VesselModel>> models;
  models.emplace_back("neuro (curved: siphon, arch)", CaseGenerator::neuro());
  models.emplace_back("neuro_stenosis", CaseGenerator::neuro_stenosis());
  models.emplace_back("helix r 6 pitch 8", CaseGenerator::helix(6.0, 8.0, 3.0, 1.0, 90));
  models.emplace_back("tight helix r 3 pitch 12", CaseGenerator::helix(3.0, 12.0, 2.0, 0.8, 80));
  for (int cycles = 1; cycles <= 3; ++cycles) {
    models.emplace_back("graph " + std::to_string(cycles) + " cycles (confluences, loops)",
                        CaseGenerator::random_graph(static_cast<std::uint64_t>(cycles), cycles));
  }
  RandomTreeOptions tree;
  tree.segments = 20;
  models.emplace_back("random tree", CaseGenerator::random_tree(4, tree));
  for (const auto& [name, model] : models) {
    for (int m : {8, 16}) {
      MeshOptions options;
      options.ring_points = m;
      const VesselSurface surface = build_vessel_surface(model, options);
      ASSERT_TRUE(surface.ok()) << name << ": " << surface.error;
      const test::ProfileError e = test::worst_along_segments(model, surface);
      std::printf("%s, M %d: worst %+.2f %% over %d cuts\n", name.c_str(), m, 100.0 * e.worst, e.samples);
      EXPECT_GT(e.samples, 100) << name;
      EXPECT_LT(std::abs(e.worst), 0.03) << name << " M " << m << ": " << e.worst_surface << " mm for "
                                         << e.worst_input << " at arc " << e.worst_arc;
    }
  }
}

// Real centrelines are not evenly spaced or smooth: VMTK's test aorta takes a 0.08 mm step right
// after a 0.76 mm one, and DBiharMesher's 227A jitters 0.1-0.3 mm from point to point on a 0.5 mm
// lumen. Two such lines made here (a 4.4 mm vessel on a 40 mm arc with VMTK's step pattern; a
// 0.55 mm vessel with +-0.12 mm of lateral jitter every 0.3 mm) mesh within 3 % of the input radius
// cut across the axis. Cut normal to the refined curve's central difference instead (the probe
// before), single samples read +5 % and more: the uniform Catmull-Rom curve doubles back inside
// the short step, and the jitter tilts the cut; the lumen is round there (the cut's nearest wall
// point stays at the input radius).
TEST(RadiusFidelity, JitteryUnevenCentrelinesMeshWithinThreePercentAcrossTheirAxis) {
  VesselModel arc_model;
  Segment arc;
  arc.id = 1;
  const double steps[] = {0.76, 0.08, 0.33, 0.34, 0.29, 0.22};
  double t = 0.0;
  for (int i = 0; t < 60.0; t += steps[i % 6], ++i) {
    const double angle = t / 40.0;
    const double lateral = 0.01 * std::sin(2.3 * i * i + 0.7 * i);  // VMTK's points wander ~0.01 mm off a smooth line
    arc.points.push_back({{40.0 * (1.0 - std::cos(angle)), lateral, 40.0 * std::sin(angle)}, 4.4});
  }
  arc_model.segments.push_back(arc);
  VesselModel jitter_model;
  Segment jittery;
  jittery.id = 1;
  for (int i = 0; i <= 100; ++i) {
    const double dx = 0.12 * std::sin(2.3 * i * i + 0.7 * i);  // deterministic, uncorrelated from point to point
    const double dy = 0.12 * std::cos(1.7 * i * i + 0.3 * i);
    jittery.points.push_back({{dx, dy, 0.3 * i}, 0.55});
  }
  jitter_model.segments.push_back(jittery);
  for (const auto& [name, model] : {std::pair<const char*, const VesselModel*>{"arc, VMTK's steps", &arc_model},
                                    std::pair<const char*, const VesselModel*>{"jittery 0.55 mm", &jitter_model}}) {
    const VesselSurface surface = build_vessel_surface(*model);
    ASSERT_TRUE(surface.ok()) << name << ": " << surface.error;
    double worst = 0.0;
    double worst_kinked = 0.0;
    const std::vector<test::SampleError> across = test::errors_along_segments(*model, surface);
    const std::vector<test::SampleError> kinked = test::errors_along_segments(*model, surface, 0.0);
    for (const test::SampleError& e : across) worst = std::max(worst, std::abs(e.error));
    for (const test::SampleError& e : kinked) worst_kinked = std::max(worst_kinked, std::abs(e.error));
    std::printf("%s: worst %.2f %% across the axis, %.2f %% normal to the kinked curve (%zu cuts)\n", name, 100.0 * worst,
                100.0 * worst_kinked, across.size());
    EXPECT_GT(across.size(), 100u) << name;
    EXPECT_LT(worst, 0.03) << name;
    EXPECT_GT(worst_kinked, 0.05) << name << ": the kinked probe no longer tilts here; the test shows nothing";
  }
}

}  // namespace
}  // namespace cathbox::vessel
