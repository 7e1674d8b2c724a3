// A thrombectomy stack at the hand with a box on every tool (`cathbox session run --box
// TOOL=WHERE`): every tool's hand force within the box's 5 N full scale (issue 29, "the feel").
// The M1 Solumbra run's access, to the microwire drawn out of the microcatheter: the aspiration
// catheter advanced over the microcatheter to 100 mm and parked there. Its tip, steered by the
// microcatheter while advanced, once relaxed back when parked and pressed the microcatheter held
// at it into the wall: 4.0 N parked, 8.3 N as the wire came out (118 ticks over the full scale,
// record format 38); now it keeps the microcatheter's lean (Simulator::tip_lean_held).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "hand_force_trace.hpp"
#include "session/tool_forces.hpp"

namespace cathbox::session {
namespace {

TEST(ThrombectomyFeel, TheSolumbraAccessKeepsEveryToolWithinTheBoxsFullScale) {
  ToolForces forces;
  Metrics metrics;
  ASSERT_TRUE(test::run_scripted(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro_thrombectomy_m1_solumbra.case",
                                 std::string(CATHBOX_SOURCE_DIR) + "/tests/host/session/data/solumbra_access_wire_out.actions",
                                 forces, metrics));
  std::printf("%s", forces.format().c_str());
  ASSERT_EQ(forces.tools().size(), 4U);
  EXPECT_EQ(forces.full_scale_mN(), test::kFullScale_mN);
  for (const ToolForces::Tool& k : forces.tools()) {
    EXPECT_LE(k.peak_mN, test::kFullScale_mN) << k.name << " at " << 1e-6 * static_cast<double>(k.peak_us) << " s";
    EXPECT_EQ(k.over_full_scale, 0) << k.name;
  }
}

}  // namespace
}  // namespace cathbox::session
