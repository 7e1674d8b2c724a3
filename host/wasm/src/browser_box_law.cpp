#include "wasm/browser_box_law.hpp"

#include "device/force_law_command.hpp"

namespace cathbox::wasm {

void BrowserBoxLaw::configure(const BoxLawConfig& config) {
  session::PassiveLawLimits limits;
  limits.full_scale_mN = config.full_scale_mN;
  limits.slew_mN_per_ms = config.slew_mN_per_ms;
  limits.tick_ms = config.command_period_ms;
  passive_ = session::PassiveLaw(limits);
  mode_ = config.mode;
}

cbx_command_report BrowserBoxLaw::command(const tool::ForceLaw& session_law, double box_offset_mm,
                                          double box_offset_rad, const BoxReading& reading) {
  // As HandMapping::law_to_box: the law's positions in the box's frame.
  tool::ForceLaw law = session_law;
  law.insertion0_mm += box_offset_mm;
  law.rotation0_rad += box_offset_rad;
  const session::ShapedLaw shaped = passive_.shape(law, session::BoxReadback{reading.force_mN, reading.speed_mm_s});
  return device::force_law_command(shaped.law, mode_, shaped.out_min_mN, shaped.out_max_mN);
}

}  // namespace cathbox::wasm
