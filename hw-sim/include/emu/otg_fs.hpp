#pragma once
// The STM32F411's USB OTG FS core in device mode, slave (no DMA), as RM0383 chapter 22
// describes it, for the registers the firmware uses: global (GAHBCFG, GUSBCFG, GRSTCTL,
// GINTSTS/GINTMSK, GRXSTSP, GRXFSIZ, DIEPTXF0/1..3, GCCFG), device (DCFG, DCTL, DSTS,
// DIEPMSK, DOEPMSK, DAINT, DAINTMSK), endpoints 0..3 (DIEPCTL/INT/TSIZ, DTXFSTS, DOEPCTL/INT/
// TSIZ), PCGCCTL and the FIFO windows. The host side (what the bus delivers: bus reset,
// enumeration done, SOF, suspend/resume, SETUP and OUT packets, IN tokens) is the other half of
// the API, driven by the emulator's USB host (image_emulator.cpp).
#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace cathbox::emu {

class OtgFs {
 public:
  static constexpr uint32_t kSize = 0x21000u;  // registers, FIFO windows, FIFO RAM view
  static constexpr uint32_t kFifoWords = 320u;  // 1.25 KiB of FIFO RAM

  void reset();
  // Register access from the CPU (offset from 0x50000000). Returns false for a register no
  // model implements.
  bool read(uint32_t offset, uint32_t& value);
  bool write(uint32_t offset, uint32_t value);
  [[nodiscard]] static const char* register_name(uint32_t offset);
  // The interrupt line (IRQ 67).
  [[nodiscard]] bool irq() const;

  // ---- the bus (host side) ----
  [[nodiscard]] bool connected() const;  // core powered, device mode, D+ pull-up on (SDIS clear)
  // Times the pull-up went off (soft disconnect, power down, a chip reset while connected): a
  // host sees each, however short (a hub detects a disconnect within 2.5 us).
  [[nodiscard]] uint64_t disconnects() const { return disconnects_; }
  void bus_reset();                       // USBRST, then ENUMDNE (full speed)
  void sof();                             // start of frame: SOF, frame number + 1
  void suspend();
  void resume();
  [[nodiscard]] bool suspended() const { return suspended_; }
  // A SETUP packet to endpoint 0: always accepted (clears endpoint 0's STALL).
  void setup(std::span<const uint8_t, 8> packet);
  // An OUT data packet; false = NAK (endpoint not enabled, NAK set, or the RX FIFO full).
  enum class Handshake { kAck, kNak, kStall };
  Handshake out(uint32_t ep, std::span<const uint8_t> data);
  // An IN token: the packet the device has queued (ACK), NAK, or STALL.
  Handshake in(uint32_t ep, std::vector<uint8_t>& data);
  [[nodiscard]] uint8_t address() const { return static_cast<uint8_t>((dcfg_ >> 4) & 0x7Fu); }

 private:
  struct RxEntry {
    uint32_t status;
    std::vector<uint32_t> words;
    uint32_t done_ep;    // for a completion entry: which OUT endpoint's interrupt it raises
    uint32_t done_flag;  // DOEPINT bit to set when popped (STUP or XFRC), 0 for data
  };
  struct InEp {
    uint32_t ctl = 0, intr = 0, tsiz = 0;
    std::deque<uint32_t> fifo;
  };
  struct OutEp {
    uint32_t ctl = 0, intr = 0, tsiz = 0;
  };
  [[nodiscard]] uint32_t gintsts() const;
  [[nodiscard]] uint32_t daint() const;
  [[nodiscard]] uint32_t rx_words() const;
  [[nodiscard]] uint32_t tx_depth(uint32_t ep) const;
  void flush_tx(uint32_t number);
  bool write_register(uint32_t offset, uint32_t value);

  uint32_t gahbcfg_ = 0, gusbcfg_ = 0, gintsts_ = 0, gintmsk_ = 0, grxfsiz_ = 0, gccfg_ = 0;
  std::array<uint32_t, 4> dieptxf_{};  // [0] = DIEPTXF0 (HNPTXFSIZ)
  uint32_t dcfg_ = 0, dctl_ = 0, diepmsk_ = 0, doepmsk_ = 0, daintmsk_ = 0, pcgcctl_ = 0;
  uint32_t frame_ = 0;
  bool suspended_ = false;
  uint64_t disconnects_ = 0;
  std::array<InEp, 4> in_{};
  std::array<OutEp, 4> out_{};
  std::deque<RxEntry> rx_;
  std::optional<RxEntry> reading_;  // popped by GRXSTSP, its data read through FIFO 0
  size_t read_index_ = 0;
};

}  // namespace cathbox::emu
