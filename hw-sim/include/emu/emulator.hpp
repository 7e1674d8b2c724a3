#pragma once
// cathbox-emu's box: firmware/core (the same code as the board) on a simulated HAL (SimBoard),
// the physical model (BoxModel: hand, tool, rollers, collet, encoders, brake or motor), the
// STM32 ROM DfuSe bootloader with its flash, fault injection, and the socket server. Time is
// explicit: advance() runs the box for a span of simulated time (deterministic: virtual time
// in tests), and the cathbox-emu executable calls it against the wall clock (real time).
//
// Schedule inside advance(): physics and encoder edges every 10 us, the core's control tick
// every 100 us (10 kHz), one USB frame every 1000 us (OUT reports and control requests in,
// one IN report out), the core's background work once per frame.
#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "emu/box_model.hpp"
#include "emu/dfu_bootloader.hpp"
#include "emu/emu_server.hpp"
#include "emu/fault_injector.hpp"
#include "emu/flash_memory.hpp"
#include "emu/result.hpp"
#include "emu/sim_board.hpp"
#include "protocol/cbx_feature_reports.h"
#include "protocol/cbx_state_report.h"

namespace cathbox::emu {

struct EmuOptions {
  bool motor = false;        // DC motors (push and resist) instead of brakes
  bool calibrated = true;    // the board's settings store holds a calibration
  std::string serial = "EMU-0001";
  uint64_t seed = 1;         // fault injection and noise
};

enum class BoardMode { kApplication, kBootloader, kNoFirmware };

// The calibration `cathbox calibrate` would store for the modelled box: its encoders, its
// actuators' full scale, a linear output curve (the factory store here, the image's tests).
[[nodiscard]] cbx_calibration model_calibration(BoxModel& model);

class Emulator final : public EmuServer::Handler {
 public:
  static constexpr uint64_t kPhysicsStep_us = 10;
  static constexpr uint64_t kTick_us = 100;
  static constexpr uint64_t kFrame_us = 1000;

  explicit Emulator(EmuOptions options = {});
  ~Emulator() override;
  Emulator(const Emulator&) = delete;
  Emulator& operator=(const Emulator&) = delete;

  // Serves the box on a socket (see EmuServer).
  [[nodiscard]] Status listen(const std::string& path);
  // Runs the box for `us` microseconds of simulated time.
  void advance(uint64_t us);
  // Handles pending socket input now, without advancing time (real-time main loop).
  void service();
  [[nodiscard]] uint64_t now_us() const { return now_us_; }

  // The world around the box.
  [[nodiscard]] BoxModel& model() { return model_; }
  [[nodiscard]] SimBoard& board() { return board_; }
  [[nodiscard]] FlashMemory& flash() { return flash_; }
  [[nodiscard]] FaultInjector& faults() { return faults_; }
  [[nodiscard]] EmuServer* server() { return server_.get(); }
  void set_hand(int axis, HandScript script) { model_.set_script(axis, std::move(script), now_us_); }
  void set_estop(bool pressed) { board_.estop_pressed = pressed; }
  // Pretends to be a box of another protocol major version: byte 1 of every report the box
  // sends is rewritten (with a valid CRC), as a future firmware would send it.
  void set_wire_version(uint8_t version) { wire_version_ = version; }
  // Unplugs the box (all connections close, new ones are refused) for duration_us.
  void unplug(uint64_t duration_us);
  // The recovery straps: BOOT0 level and a reset (as the lab rig's GPIO drives them).
  void set_boot0(bool high) { boot0_ = high; }
  void reset();

  [[nodiscard]] BoardMode mode() const { return mode_; }
  [[nodiscard]] uint8_t bootloader_state() const { return bootloader_.state(); }
  // The firmware's own view (what the next IN report carries), for tests.
  [[nodiscard]] cbx_state_report core_state();
  // The true encoder position (counts) of the physical model.
  [[nodiscard]] int64_t true_count(int axis) const { return model_.state(axis).count; }
  [[nodiscard]] uint64_t in_reports_sent() const { return in_reports_; }
  [[nodiscard]] uint64_t out_reports_delivered() const { return out_delivered_; }
  // Quadrature transitions fed to the core (both axes, noise included).
  [[nodiscard]] uint64_t edges_fed() const { return edges_fed_; }

  // EmuServer::Handler
  [[nodiscard]] bool attached(uint16_t& vid, uint16_t& pid) override;
  void on_out(std::span<const uint8_t> report) override;
  [[nodiscard]] bool on_control(const cbx_usb_setup& setup, std::span<const uint8_t> data,
                                std::vector<uint8_t>& reply) override;

 private:
  struct Core;  // holds firmware/core's cbx_core (kept out of this header)
  struct Pending {
    uint64_t due_us;
    std::array<uint8_t, 64> report;
  };
  void boot(bool to_bootloader);
  void transitions();
  void physics_step();
  void feed_edges(int axis, int64_t steps);
  void edge(int axis, int direction);
  void usb_frame();
  void deliver_out(const std::array<uint8_t, 64>& report);
  void send_in(std::array<uint8_t, 64> report);
  void rewrite_version(std::span<uint8_t> report) const;

  EmuOptions options_;
  std::unique_ptr<Core> core_;
  SimBoard board_;
  BoxModel model_;
  FlashMemory flash_;
  DfuBootloader bootloader_;
  FaultInjector faults_;
  std::unique_ptr<EmuServer> server_;
  BoardMode mode_ = BoardMode::kApplication;
  bool boot0_ = false;
  uint64_t now_us_ = 0;
  uint64_t unplugged_until_us_ = 0;
  std::array<uint8_t, 2> edge_phase_{};  // quadrature phase fed to the core, 0..3
  std::deque<Pending> out_queue_;        // delayed OUT reports
  std::deque<Pending> in_queue_;         // delayed IN reports
  uint64_t in_reports_ = 0;
  uint64_t out_delivered_ = 0;
  uint64_t edges_fed_ = 0;
  uint8_t wire_version_ = CBX_PROTOCOL_VERSION;
};

}  // namespace cathbox::emu
