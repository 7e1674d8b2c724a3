#pragma once
// Exit codes of the `cathbox` command (documented in host/cli/README.md).
namespace cathbox::cli {
inline constexpr int kExitOk = 0;            // success
inline constexpr int kExitFailure = 1;       // the operation ran and failed (test failed, verify mismatch)
inline constexpr int kExitBadInput = 2;      // bad command line, bad file, bad image: nothing was changed
inline constexpr int kExitNoDevice = 3;      // no box / bootloader / emulator found or it went away
inline constexpr int kExitIncompatible = 4;  // the box speaks an incompatible protocol version
inline constexpr int kExitDeviceError = 5;   // the box answered with an error or a fault
}  // namespace cathbox::cli
