#pragma once
// The tool's local force law is the base vocabulary type (sim/base/include/base/force_law.hpp),
// so that host/device can build the box's command from it without depending on the simulator.
#include "base/force_law.hpp"

namespace cathbox::tool {
using ForceLaw = base::ForceLaw;
}  // namespace cathbox::tool
