#pragma once
// Exit codes of the `cathbox` command: the one set every Cathbox program uses, defined in
// sim/base/include/base/exit_codes.hpp (documented in host/session/README.md).
#include "base/exit_codes.hpp"

namespace cathbox::cli {
using base::kExitBadInput;
using base::kExitDeviceError;
using base::kExitFailure;
using base::kExitIncompatible;
using base::kExitNoDevice;
using base::kExitNoDisplay;
using base::kExitOk;
}  // namespace cathbox::cli
