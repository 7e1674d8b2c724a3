// Stability on every bundled vessel case: 10^5 steps (100 s of virtual time) of random insert
// and rotate inputs on every tool of the case: no NaN anywhere (every step), and no simulated
// node outside the lumen by more than 10% of its radius (exact mesh distance, every 25 steps).
// cases/seed_catheter.hclm is the seed's catheter centreline (lumen radius 0.03 mm), not a
// vessel a tool fits in, so it is not a case here.
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"
#include "tool/mesh_wall.hpp"
#include "tool/simulator.hpp"

namespace cathbox::tool {
namespace {

struct StabilityCase {
  const char* file;
  double max_insertion_mm;  // keep the tools within the vessel's length
};

class Stability : public ::testing::TestWithParam<StabilityCase> {};

TEST_P(Stability, RandomInputsKeepEveryNodeInTheLumen) {
  const std::string path = std::string(CATHBOX_SOURCE_DIR) + "/cases/" + GetParam().file;
  const CaseParse c = load_case(path);
  ASSERT_TRUE(c) << c.error().message;
  WorldBuild world = build_world(*c);
  ASSERT_TRUE(world.ok()) << world.error().message;
  const auto* mesh = dynamic_cast<const MeshWall*>(&(*world)->wall());
  ASSERT_NE(mesh, nullptr);
  Simulator sim((*world)->wall(), c->tools, (*world)->entry());
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> speed(-40.0, 80.0);     // mm/s, forward on average
  std::uniform_real_distribution<double> spin(-6.0, 6.0);        // rad/s
  std::uniform_int_distribution<int> hold(50, 400);              // ms per input
  const std::size_t tools = sim.tool_count();
  std::vector<double> v(tools, 0.0), w(tools, 0.0);
  std::vector<int> until(tools, 0);
  const double max_insertion = GetParam().max_insertion_mm;
  double worst = 0.0;
  for (int step = 0; step < 100000; ++step) {
    for (std::size_t t = 0; t < tools; ++t) {
      if (step >= until[t]) {
        v[t] = speed(rng);
        w[t] = spin(rng);
        until[t] = step + hold(rng);
      }
      const double ins = std::clamp(sim.insertion_mm(t) + v[t] * 1e-3, 0.0, max_insertion);
      sim.set_insertion(t, ins);
      sim.set_rotation(t, sim.rotation_rad(t) + w[t] * 1e-3);
    }
    sim.step();
    for (std::size_t t = 0; t < tools; ++t) {
      ASSERT_TRUE(std::isfinite(sim.hand_force_mN(t)) && std::isfinite(sim.hand_torque_mNmm(t))) << "step " << step;
      ASSERT_TRUE(std::isfinite(sim.tip(t).position_mm.x)) << "step " << step;
    }
    if (step % 25 != 0) continue;
    for (std::size_t t = 0; t < tools; ++t) {
      const Rod& rod = sim.rod(t);
      for (std::size_t k = rod.first_free_node(); k < rod.node_total(); ++k) {
        const glm::dvec3& x = rod.positions()[k];
        ASSERT_TRUE(std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z)) << "step " << step;
        const std::optional<double> d = mesh->tree().signed_distance(x);
        ASSERT_TRUE(d.has_value());
        const double r = rod.node_radius_mm(k);
        const double out = (*d + r) / r;  // > 0: the node's surface is past the wall
        worst = std::max(worst, out);
        ASSERT_LE(out, 0.10) << GetParam().file << ": tool " << rod.spec().name << " node " << k << " at step " << step
                             << " is outside the lumen by " << out * 100.0 << "% of its radius";
      }
    }
  }
  RecordProperty("worst_penetration_percent", std::to_string(worst * 100.0));
}

INSTANTIATE_TEST_SUITE_P(BundledCases, Stability,
                         ::testing::Values(StabilityCase{"neuro.case", 160.0}, StabilityCase{"neuro_aneurysm.case", 160.0},
                                           StabilityCase{"neuro_stenosis.case", 160.0},
                                           StabilityCase{"y_bifurcation.case", 85.0}),
                         [](const ::testing::TestParamInfo<StabilityCase>& param_info) {
                           std::string name = param_info.param.file;
                           return name.substr(0, name.find('.'));
                         });

}  // namespace
}  // namespace cathbox::tool
