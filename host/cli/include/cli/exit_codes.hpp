#pragma once
// Exit codes of the `cathbox` command: the one set every Cathbox program uses, defined in
// host/session/include/session/exit_codes.hpp (documented in host/session/README.md).
#include "session/exit_codes.hpp"

namespace cathbox::cli {
using session::kExitBadInput;
using session::kExitDeviceError;
using session::kExitFailure;
using session::kExitIncompatible;
using session::kExitNoDevice;
using session::kExitNoDisplay;
using session::kExitOk;
}  // namespace cathbox::cli
