#pragma once
// The exit codes of every Cathbox program (cathbox, cathbox-trainer, cathbox-server): one set,
// documented in host/session/README.md ("Exit codes"). host/cli re-exports them as
// cathbox::cli::kExit*.
namespace cathbox::base {
inline constexpr int kExitOk = 0;            // success
inline constexpr int kExitFailure = 1;       // the operation ran and failed (test failed, verify mismatch,
                                             // a replayed state differs)
inline constexpr int kExitBadInput = 2;      // bad command line, bad file (case, record, image): nothing changed
inline constexpr int kExitNoDevice = 3;      // no box / bootloader / emulator found, or it went away
inline constexpr int kExitIncompatible = 4;  // the box speaks an incompatible protocol version
inline constexpr int kExitDeviceError = 5;   // the box answered with an error or a fault
inline constexpr int kExitNoDisplay = 6;     // no display, or no OpenGL 3.3 (the trainer)
}  // namespace cathbox::base
