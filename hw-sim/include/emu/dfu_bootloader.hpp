#pragma once
// The STM32 ROM DFU bootloader as seen over USB endpoint 0: the DFU 1.1 state machine with
// ST's DfuSe extensions (set address, sector erase, download to blocks >= 2, upload, leave by
// a zero-length download), bwPollTimeout from the flash timings, errors as the ROM reports them.
// Time is the emulator's (virtual or real) microsecond clock.
#include <cstdint>
#include <span>
#include <vector>

#include "emu/flash_memory.hpp"
#include "protocol/cbx_emu_frame.h"

namespace cathbox::emu {

class DfuBootloader {
 public:
  static constexpr uint16_t kTransferSize = 2048;
  explicit DfuBootloader(FlashMemory& flash) : flash_(flash) {}

  // Handles one control request. Returns false to stall; `reply` receives the IN data stage.
  [[nodiscard]] bool control(const cbx_usb_setup& setup, std::span<const uint8_t> out, uint64_t now_us,
                             std::vector<uint8_t>& reply);
  // True once the host asked to leave and read the manifest status: the board resets.
  [[nodiscard]] bool leave_requested() const { return leave_; }
  // Back to power-on state (dfuIDLE), e.g. after a reset into the bootloader.
  void reset();
  [[nodiscard]] uint8_t state() const { return state_; }
  [[nodiscard]] uint32_t address_pointer() const { return pointer_; }

 private:
  enum class Op { kNone, kSetAddress, kErase, kWrite, kLeave };
  void fail(uint8_t status);
  void get_status(uint64_t now_us, std::vector<uint8_t>& reply);
  [[nodiscard]] bool dnload(uint16_t block, std::span<const uint8_t> data);
  [[nodiscard]] bool upload(uint16_t block, uint16_t length, std::vector<uint8_t>& reply);
  // Runs the pending operation; returns its busy time in ms.
  uint32_t execute();

  FlashMemory& flash_;
  uint8_t state_ = 2;   // CBX_DFU_IDLE
  uint8_t status_ = 0;  // CBX_DFU_OK
  uint32_t pointer_ = FlashMemory::kBase;
  Op op_ = Op::kNone;
  uint32_t op_address_ = 0;
  std::vector<uint8_t> op_data_;
  uint64_t busy_until_us_ = 0;
  bool leave_ = false;
};

}  // namespace cathbox::emu
