#pragma once
// The command that makes the box render a tool's local force law (base/force_law.hpp)
// between simulation updates. The law must be in the box's own frame: positions in mm and rad
// from the box's count zero (session::HandMapping::law_to_box gives that). The tool's law is
// the force on the hand, positive resisting insertion; the box's (protocol/README.md) is its
// output, positive pushing in: out = offset - k (pos - pos0) - b vel, in µm, µrad, mN, µN·m.
#include <cstdint>

#include "base/force_law.hpp"
#include "protocol/cbx_command_report.h"

namespace cathbox::device {

// Negative gains from the solver are not sent (a box must never be asked to push back
// harder the further it goes the wrong way); values beyond int32 saturate.
[[nodiscard]] cbx_command_report force_law_command(const base::ForceLaw& box_frame_law, std::uint8_t mode);
// The same with the insertion output held within [out_min_mN, out_max_mN] (+ pushes in).
[[nodiscard]] cbx_command_report force_law_command(const base::ForceLaw& box_frame_law, std::uint8_t mode,
                                                   double out_min_mN, double out_max_mN);
// Outputs off (end of run, shutdown).
[[nodiscard]] cbx_command_report outputs_off_command();

}  // namespace cathbox::device
