#pragma once
// The trainee's hand as the box measures it, through BoxClient: a real box over hidapi, or the
// emulated box (cathbox-emu, started here when no box is found and stopped with the session).
// Connecting and reading the calibration block (feature reports); afterwards only the haptic
// thread uses it: poll() the newest state, send() the tool's local force law every tick.
#include <cstdint>
#include <memory>
#include <string>

#include "app/trainer_options.hpp"
#include "protocol/cbx_command_report.h"

namespace cathbox::tool {
struct ForceLaw;
}

namespace cathbox::app {

struct BoxReading {
  double insertion_mm = 0.0;  // since the session started
  double rotation_rad = 0.0;
  bool fresh = false;         // a new state arrived this tick
  std::uint16_t faults = 0;   // CBX_FAULT_* latched in the box
  bool link_up = false;
};

// Where the session's zero lies in the box's encoder counts, and the calibration.
struct BoxOrigin {
  double counts_per_mm = 1.0;
  double counts_per_rad = 1.0;
  std::int32_t insertion_count0 = 0;
  std::int32_t rotation_count0 = 0;
};

// The command that makes the box render the tool's local force law. The tool's law gives the
// force on the hand, positive resisting insertion, in the session's millimetres; the box's
// gives its output, positive pushing in, in its own micrometres from its own zero.
[[nodiscard]] cbx_command_report box_command(const tool::ForceLaw& law, const BoxOrigin& origin,
                                             std::uint8_t mode);

class BoxHand {
 public:
  // Finds the box as `choice` says (kAuto: a real box, else the emulator); `emu_program` is the
  // cathbox-emu executable to start when needed. Null with one line in `error` on failure.
  [[nodiscard]] static std::unique_ptr<BoxHand> connect(BoxChoice choice, const std::string& emu_socket,
                                                        const std::string& emu_program, std::string& error);
  ~BoxHand();
  BoxHand(const BoxHand&) = delete;
  BoxHand& operator=(const BoxHand&) = delete;

  // Haptic thread.
  [[nodiscard]] BoxReading poll();
  void send(const tool::ForceLaw& law);
  // Outputs off (end of run, shutdown).
  void release();

  [[nodiscard]] std::string describe() const;

 private:
  struct Impl;
  explicit BoxHand(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace cathbox::app
