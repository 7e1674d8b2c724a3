// The aneurysm sac: the sphere-cap volume against a finely triangulated cap closed at its neck
// (fan_closed_volume_mm3), the case file's declared sac and its errors, and the bundled right
// MCA aneurysm found in the vessel (neck at the M1 end, volume against its centre line).
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tool/aneurysm_sac.hpp"
#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"

namespace cathbox::tool {
namespace {

// A sphere of radius r at `c` from its north pole down to the circle at height -d below the
// centre (the neck), outward-oriented, `rings` x `sectors`.
void sphere_cap_mesh(const glm::dvec3& c, double r, double d, int rings, int sectors, std::vector<glm::vec3>& pos,
                     std::vector<std::uint32_t>& tri) {
  const double theta_max = std::acos(-d / r);  // polar angle of the neck circle
  pos.push_back(glm::vec3(c + glm::dvec3(0, 0, r)));
  for (int i = 1; i <= rings; ++i) {
    const double th = theta_max * i / rings;
    for (int j = 0; j < sectors; ++j) {
      const double ph = 2.0 * M_PI * j / sectors;
      pos.push_back(glm::vec3(c + r * glm::dvec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th))));
    }
  }
  const auto at = [&](int i, int j) { return static_cast<std::uint32_t>(1 + (i - 1) * sectors + (j % sectors)); };
  for (int j = 0; j < sectors; ++j) tri.insert(tri.end(), {0u, at(1, j), at(1, j + 1)});
  for (int i = 1; i < rings; ++i) {
    for (int j = 0; j < sectors; ++j) {
      tri.insert(tri.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      tri.insert(tri.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
}

TEST(AneurysmSac, SphereCapVolumeMatchesTheClosedSurface) {
  const glm::dvec3 centre(1.0, -2.0, 30.0);
  for (const double d : {0.5, 1.5, 2.5}) {
    const double r = 3.2;
    const std::optional<AneurysmSac> sac = sphere_cap_sac(centre, r, centre - glm::dvec3(0, 0, d));
    ASSERT_TRUE(sac);
    EXPECT_NEAR(sac->neck_radius_mm, std::sqrt(r * r - d * d), 1e-12);
    EXPECT_NEAR(glm::length(sac->neck_normal - glm::dvec3(0, 0, 1)), 0.0, 1e-12);
    std::vector<glm::vec3> pos;
    std::vector<std::uint32_t> tri;
    sphere_cap_mesh(centre, r, d, 200, 400, pos, tri);
    const double surface = fan_closed_volume_mm3(pos, tri, sac->neck_centre_mm);
    EXPECT_NEAR(surface / sac->volume_mm3, 1.0, 2e-3) << "d " << d;
    // A hemisphere and a whole sphere as limits of the formula.
    EXPECT_NEAR(sphere_cap_volume_mm3(r, r), 2.0 / 3.0 * M_PI * r * r * r, 1e-9);
    EXPECT_NEAR(sphere_cap_volume_mm3(r, 2.0 * r), 4.0 / 3.0 * M_PI * r * r * r, 1e-9);
  }
  EXPECT_FALSE(sphere_cap_sac(centre, 3.0, centre + glm::dvec3(0, 0, 3.5)));  // neck outside
  EXPECT_FALSE(sphere_cap_sac(centre, 3.0, centre));                          // no plane
}

constexpr const char* kTubeCase = "cathbox-case 1\ntube 0 0 0 0 1.5 0 0 20 1.5\nentry 0 0 1 0 0 1\n";

TEST(AneurysmSac, DeclaredInTheCaseFile) {
  CaseParse ok = parse_case(std::string(kTubeCase) + "aneurysm 0 0 22 3  0 0 20\n", "t.case");
  ASSERT_TRUE(ok) << ok.error().message;
  ASSERT_TRUE(ok->aneurysm);
  EXPECT_NEAR(ok->aneurysm->volume_mm3, sphere_cap_volume_mm3(3.0, 5.0), 1e-9);
  WorldBuild world = build_world(*ok);
  ASSERT_TRUE(world);
  ASSERT_TRUE((*world)->sac());
  EXPECT_EQ((*world)->sac()->segment, -1);
  const auto error_of = [](const std::string& line) {
    CaseParse bad = parse_case(std::string(kTubeCase) + line, "t.case");
    return bad ? std::string("parsed") : bad.error().message;
  };
  EXPECT_EQ(error_of("aneurysm 0 0 22 30  0 0 20\n"), "t.case:4: aneurysm: dome radius must be in [1, 15] mm");
  EXPECT_EQ(error_of("aneurysm 0 0 22 3  0 0 10\n"),
            "t.case:4: aneurysm: the neck centre must lie inside the dome sphere, off its centre");
  EXPECT_EQ(error_of("aneurysm 0 0 22 3  0 0\n"), "t.case:4: aneurysm: expected 7 values, got 6");
  EXPECT_EQ(error_of("aneurysm 0 0 22 3 0 0 20\naneurysm 0 0 22 3 0 0 20\n"), "t.case:5: aneurysm given twice");
  EXPECT_EQ(error_of("aneurysm 0 0 x 3 0 0 20\n"), "t.case:4: aneurysm: 'x' is not a finite number");
}

TEST(AneurysmSac, BundledRightMcaAneurysmIsFoundInTheVessel) {
  CaseParse c = load_case(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro_aneurysm.case");
  ASSERT_TRUE(c) << c.error().message;
  WorldBuild world = build_world(*c);
  ASSERT_TRUE(world) << world.error().message;
  const std::optional<AneurysmSac>& sac = (*world)->sac();
  ASSERT_TRUE(sac);
  const vessel::VesselModel& model = *(*world)->model();
  const vessel::Segment& seg = model.segments[*model.index_of(sac->segment)];
  EXPECT_EQ(seg.name, "right_mca_aneurysm");
  // The neck is the sac's ring at the end of the right M1 (-31, 16, 239), the normal along the
  // sac's axis, the dome beyond it (further to the patient's right).
  EXPECT_LT(glm::length(sac->neck_centre_mm - glm::dvec3(-31, 16, 239)), 0.5);
  EXPECT_NEAR(sac->neck_radius_mm, 1.2, 0.1);
  const glm::dvec3 axis = glm::normalize(seg.points.back().pos_mm - seg.points.front().pos_mm);
  EXPECT_GT(glm::dot(sac->neck_normal, axis), 0.8);
  EXPECT_LT(sac->dome_centre_mm.x, sac->neck_centre_mm.x);
  EXPECT_GT(sac->depth_mm(sac->dome_centre_mm), 2.0);
  // The closed surface (with the frusta from the neck to its ring) against the centre line's
  // frusta alone: the same sac within 5 %.
  const double line = centreline_sac_volume_mm3(seg);
  EXPECT_NEAR(sac->volume_mm3 / line, 1.0, 0.05) << "surface " << sac->volume_mm3 << " mm3, centre line " << line << " mm3";
  // The healthy vessel has none.
  CaseParse healthy = load_case(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro.case");
  ASSERT_TRUE(healthy);
  WorldBuild hw = build_world(*healthy);
  ASSERT_TRUE(hw);
  EXPECT_FALSE((*hw)->sac());
}

}  // namespace
}  // namespace cathbox::tool
