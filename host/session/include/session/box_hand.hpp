#pragma once
// The trainee's hand as the box measures it, through BoxClient: a real box over hidapi, or the
// emulated box (cathbox-emu, started here when asked to and stopped with the hand). Connecting
// and reading the calibration are feature reports (before the run); then, on the haptic
// thread, read() polls the newest state (counts -> the held tool's position, HandMapping) and
// feel() sends the held tool's local force law (HandMapping -> device::force_law_command).
// The keyboard can move the held tool on top of the box (KeyboardInput).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/result.hpp"
#include "device/box_client.hpp"
#include "device/clock.hpp"
#include "session/emulator_process.hpp"
#include "session/hand.hpp"
#include "session/hand_mapping.hpp"
#include "session/keyboard_input.hpp"
#include "session/passive_law.hpp"

namespace cathbox::session {

enum class BoxSource {
  kAuto,      // a real box if one is found, else the emulator
  kEmulator,  // the emulator (at `emu_socket`, or started on a socket of its own)
  kSerial,    // the real box whose serial is `serial`
};

struct BoxHandOptions {
  BoxSource source = BoxSource::kAuto;
  std::string emu_socket;              // connect to the emulator here; empty: start emu_program
  std::string emu_program;             // the cathbox-emu executable
  std::vector<std::string> emu_args;   // extra arguments when starting it (e.g. hand scripts)
  std::string serial;                  // kSerial: which real box
  KeyboardInput* keyboard = nullptr;   // the keyboard on top of the box (optional)
  // A rig with a box per tool: this box always drives `tool` and renders its force law; the
  // tool in the trainee's other hand has a box of its own. None: the box drives the held tool.
  std::optional<std::size_t> tool;
  double dt_s = 1e-3;                  // the tick
};

class BoxHand final : public Hand {
 public:
  // Finds the box as `options` say, or one line saying why not.
  [[nodiscard]] static base::Result<std::unique_ptr<BoxHand>> connect(const BoxHandOptions& options);
  // Over a client connected elsewhere on `clock` (tests: the emulator in-process, virtual time).
  [[nodiscard]] static base::Result<std::unique_ptr<BoxHand>> attach(std::unique_ptr<device::BoxClient> client,
                                                                     const BoxHandOptions& options);
  ~BoxHand() override;

  [[nodiscard]] HandKind kind() const override { return HandKind::kBox; }
  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] std::optional<DeviceRecord> device() const override;
  void hold(std::size_t tool, const ToolCommand& at) override;
  void restart(std::size_t tool, const ToolCommand& at) override;
  void read(std::int64_t tick, TickInput& input) override;
  void feel(const HandFeedback& feedback) override;
  // A box bound to a tool renders that tool's law, held or not.
  [[nodiscard]] bool feels_every_tool() const override { return tool_.has_value(); }
  void release() override;

  [[nodiscard]] const HandMapping& mapping() const { return mapping_; }
  // The tool this box is bound to (BoxHandOptions::tool), if any.
  [[nodiscard]] std::optional<std::size_t> bound_tool() const { return tool_; }
  // The box's link and faults, as TickInput::box reports them.
  [[nodiscard]] BoxStatus status() const;
  [[nodiscard]] const device::BoxClient& client() const { return *client_; }
  // What makes the sent law passive (passive_law.hpp), for tests and the trainer's panel.
  [[nodiscard]] const PassiveLaw& passive_law() const { return passive_; }

 private:
  BoxHand() = default;
  // The calibration and the box's limits: the mapping and the passive law.
  [[nodiscard]] base::Status<> init();

  device::SystemClock clock_;                    // for a client this hand connects
  std::unique_ptr<EmulatorProcess> emulator_;    // before the client: destroyed after it
  std::unique_ptr<device::BoxClient> client_;
  device::BoxState state_;
  cbx_calibration calibration_{};
  HandMapping mapping_;
  PassiveLaw passive_;
  std::uint8_t mode_ = 0;
  KeyboardInput* keyboard_ = nullptr;
  double dt_s_ = 1e-3;
  std::string kind_;
  std::optional<std::size_t> tool_;
  bool bound_started_ = false;  // a bound box took its tool where it was
};

}  // namespace cathbox::session
