// Public real centrelines and surfaces, imported and meshed as a user would, the mesh measured at
// every sample against the imported (median-filtered) radius, cut across the input axis
// (radius_probe.hpp; issue 31: within 5 % on real data). The bundled SOFA aneurysm lumen always
// runs; the others are not bundled (vmtk/vmtk-test-data has no licence; BlueFern/DBiharMesher is
// GPL-2.0; stEVE_bench is MIT but not needed in the tree), so they are read from the folder named
// by CATHBOX_REAL_DATA and skipped without it:
//   vmtk/vmtk-test-data @ 7f5abc0: input/aorta-centerline.vtp, input/aorta-surface.stl,
//     input/aorta-surface-open-ends.stl,
//     centerlinereference/test_vmtkcenterlines_test_carotidprofiles_centerlines.vtp
//   BlueFern/DBiharMesher @ 9b7c903: data/721A_Centreline.vtk, data/227A_Centreline.vtk
//   lkarstensen/stEVE_bench @ 1c7640e (MIT): the 25 curves of data/dualdevicenav/Centrelines_comb/
//     (an aortic arch with its supra-aortic vessels) as one dualdevicenav_centrelines_comb.mrk.json,
//     the files' "markups" lists concatenated in file-name order (worst -2.6 %, held to 3 %), and
//     its 21 numbered curves alone ("Centerline curve (N)", without the named LCCA, RCCA, LVA, RVA)
//     as dualdevicenav_21_numbered_curves.mrk.json (5 components; worst +2.7 %, held to 3 %). They
//     read +10.9 % and +5.7 % while the probe counted a carotid siphon's other limb within its reach
//     and a loop where the cut grazed a widening lumen's shoulder, and the mesher's rings jumped
//     from 1 mm to 0.19 mm apart at a radius ramp (radius_real_defects_test.cpp in tests/sim/vessel).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "radius_probe.hpp"
#include "vessel/mesh_analysis.hpp"
#include "vessel/vessel_mesher.hpp"
#include "vessel_import/importer.hpp"

namespace cathbox::vessel_import {
namespace {

// The file: a bundled one (from the source tree), or one named relative to CATHBOX_REAL_DATA.
std::string real_file(const std::string& name) {
  if (name.rfind("cases/", 0) == 0) return std::string(CATHBOX_SOURCE_DIR) + "/" + name;
  const char* dir = std::getenv("CATHBOX_REAL_DATA");
  if (dir == nullptr || *dir == '\0') return {};
  const std::string path = (std::filesystem::path(dir) / name).string();
  return std::filesystem::exists(path) ? path : std::string();
}

struct RealFile {
  const char* name;
  double worst;  // bound on the worst sample's |error|
};

class RealFiles : public ::testing::TestWithParam<RealFile> {};

TEST_P(RealFiles, MeshWithinFivePercentOfTheirRadiusAtEverySample) {
  const char* name = GetParam().name;
  const std::string path = real_file(name);
  if (path.empty()) GTEST_SKIP() << name << ": CATHBOX_REAL_DATA not set or the file not there";
  const ImportResult r = import_centerlines(path);
  ASSERT_TRUE(r.ok()) << r.errors.front().to_string();
  const vessel::VesselSurface surface = vessel::build_vessel_surface(r.model);
  ASSERT_TRUE(surface.ok()) << surface.error;
  const vessel::MeshAnalysis a = vessel::analyze_mesh(surface.mesh);
  EXPECT_TRUE(a.closed() && a.manifold() && a.consistently_oriented());
  const std::vector<vessel::test::SampleError> errors = vessel::test::errors_along_segments(r.model, surface);
  ASSERT_GT(errors.size(), 100u);
  std::vector<double> abs_errors;
  for (const vessel::test::SampleError& e : errors) abs_errors.push_back(std::abs(e.error));
  std::sort(abs_errors.begin(), abs_errors.end());
  const auto worst = std::max_element(errors.begin(), errors.end(), [](const auto& x, const auto& y) {
    return std::abs(x.error) < std::abs(y.error);
  });
  std::printf("%s: %zu triangles; radius error median %.2f %%, p95 %.2f %%, worst %+.2f %% (segment %d arc %.2f mm: %.3f mm "
              "for %.3f) over %zu cuts\n",
              name, a.triangles, 100.0 * abs_errors[abs_errors.size() / 2],
              100.0 * abs_errors[abs_errors.size() * 95 / 100], 100.0 * worst->error, worst->segment_id, worst->arc,
              worst->surface, worst->input, errors.size());
  EXPECT_LT(std::abs(worst->error), GetParam().worst) << name;
}

// The bundled SOFA lumen (decimated to 4,000 triangles) has the hardest flank: its thin side
// branch (segment 3) widens from 0.32 to 0.66 mm in 1.4 mm with points 0.12-0.51 mm apart. Its
// worst sample was -7.6 % while the smoother's umbrella step slid unevenly spaced points along
// the line with their radii; with the step normal to the neighbours' chord (and the skeleton's
// centring reaching its whole first distance) it is +2.5 %.
INSTANTIATE_TEST_SUITE_P(Public, RealFiles,
                         ::testing::Values(RealFile{"cases/sofa_aneurysm/aneurysm3D_1.ply", 0.05},
                                           RealFile{"aorta-centerline.vtp", 0.05},
                                           RealFile{"test_vmtkcenterlines_test_carotidprofiles_centerlines.vtp", 0.05},
                                           RealFile{"721A_Centreline.vtk", 0.05}, RealFile{"227A_Centreline.vtk", 0.05},
                                           RealFile{"aorta-surface.stl", 0.05}, RealFile{"aorta-surface-open-ends.stl", 0.05},
                                           RealFile{"dualdevicenav_centrelines_comb.mrk.json", 0.03},
                                           RealFile{"dualdevicenav_21_numbered_curves.mrk.json", 0.03}),
                         [](const ::testing::TestParamInfo<RealFile>& p) {
                           std::string name = std::filesystem::path(p.param.name).filename().string();
                           name = name.substr(0, name.find('.'));
                           for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

}  // namespace
}  // namespace cathbox::vessel_import
