// The trainee page's box command (host/wasm/src/browser_box_law.cpp, compiled natively here)
// against the native driver's path (host/session/src/box_hand.cpp, BoxHand::feel):
// HandMapping::law_to_box, PassiveLaw::shape, device::force_law_command, protocol/'s encoder.
// Over a run of changing laws and readbacks the page's bytes are the native driver's, but for
// the law's positions (pos0), which may differ by 1 µm / 1 µrad: the native mapping rounds the
// box's count origin to whole µm and µrad, the page computes it in double.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "device/force_law_command.hpp"
#include "protocol/cbx_command_report.h"
#include "session/hand_mapping.hpp"
#include "session/passive_law.hpp"
#include "wasm/browser_box_law.hpp"

namespace cathbox::wasm {
namespace {

constexpr double kTwoPi = 6.283185307179586;

std::array<std::uint8_t, CBX_REPORT_SIZE> encoded(cbx_command_report c) {
  c.header.version = CBX_PROTOCOL_VERSION;
  c.header.seq = 7;
  std::array<std::uint8_t, CBX_REPORT_SIZE> out{};
  EXPECT_EQ(cbx_command_encode(&c, out.data()), CBX_OK);
  return out;
}

TEST(BrowserBoxLaw, SameCommandAsBoxHand) {
  // A box calibrated 200 000 counts/m, 8192 counts/rev, connected at counts (12345, -777) while
  // the held tool was at 35.2 mm, 0.4 rad; limits 2500 mN, 100 mN/ms; a command every 5 ms.
  const std::int32_t zero_ins = 12345;
  const std::int32_t zero_rot = -777;
  session::HandMapping mapping(session::EncoderCalibration{200000, 8192});
  mapping.set_count_origin({zero_ins, zero_rot});
  mapping.hold(0, session::ToolCommand{35200, 400000});
  session::PassiveLawLimits limits;
  limits.full_scale_mN = 2500;
  limits.slew_mN_per_ms = 100;
  limits.tick_ms = 5;
  session::PassiveLaw native(limits);
  BrowserBoxLaw page;
  page.configure({2500, 100, 5, CBX_MODE_BRAKE});
  // The page's frame (js/train_box.js sendLaw): the box's position from its count zero is the
  // session's plus this.
  const double offset_mm = zero_ins * 1000.0 / 200000 - 35.2;
  const double offset_rad = zero_rot * kTwoPi / 8192 - 0.4;

  int stiff = 0;
  for (int k = 0; k < 400; ++k) {
    tool::ForceLaw law;
    law.insertion0_mm = 35.2 + 0.01 * k;
    law.force0_mN = 150.0 * std::sin(0.05 * k) + (k > 200 ? 900.0 : 0.0);  // a jump the slew limit spreads
    law.stiffness_mN_per_mm = k % 3 == 0 ? 0.0 : 20.0 * k;
    law.damping_mN_s_per_mm = 0.01 * (k % 7);
    law.rotation0_rad = 0.4 + 0.003 * k;
    law.torque0_mNmm = 2.0 * std::cos(0.1 * k);
    law.torsion_stiffness_mNmm_per_rad = 5.0;
    law.torsion_damping_mNmm_s_per_rad = 0.5;
    const double force_mN = -40.0 * std::sin(0.07 * k);
    const double speed_mm_s = 10.0 * std::cos(0.03 * k);
    const session::ShapedLaw shaped = native.shape(mapping.law_to_box(law), {force_mN, speed_mm_s});
    const cbx_command_report want = device::force_law_command(shaped.law, CBX_MODE_BRAKE, shaped.out_min_mN, shaped.out_max_mN);
    const cbx_command_report got = page.command(law, offset_mm, offset_rad, {force_mN, speed_mm_s});
    EXPECT_LE(std::abs(got.insertion.pos0 - want.insertion.pos0), 1) << "tick " << k;
    EXPECT_LE(std::abs(got.rotation.pos0 - want.rotation.pos0), 1) << "tick " << k;
    cbx_command_report same_pos = got;
    same_pos.insertion.pos0 = want.insertion.pos0;
    same_pos.rotation.pos0 = want.rotation.pos0;
    EXPECT_EQ(encoded(same_pos), encoded(want)) << "tick " << k;
    if (want.insertion.stiffness > 0) ++stiff;
  }
  EXPECT_GT(stiff, 200);  // the run exercised the stiffness and its damping floor
}

}  // namespace
}  // namespace cathbox::wasm
