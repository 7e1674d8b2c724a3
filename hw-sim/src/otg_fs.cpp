#include "emu/otg_fs.hpp"

#include <algorithm>

namespace cathbox::emu {
namespace {

// GINTSTS (RM0383 22.17.2)
constexpr uint32_t kSof = 1u << 3, kRxflvl = 1u << 4, kUsbsusp = 1u << 11, kUsbrst = 1u << 12,
                   kEnumdne = 1u << 13, kIepint = 1u << 18, kOepint = 1u << 19, kWkupint = 1u << 31;
constexpr uint32_t kGintstsClearable = kSof | (1u << 10) | kUsbsusp | kUsbrst | kEnumdne | kWkupint | (1u << 1);
// Endpoint control bits
constexpr uint32_t kEpena = 1u << 31, kEpdis = 1u << 30, kSd0pid = 1u << 28, kSnak = 1u << 27,
                   kCnak = 1u << 26, kStall = 1u << 21, kNaksts = 1u << 17;
constexpr uint32_t kXfrc = 1u << 0, kEpdisd = 1u << 1, kStup = 1u << 3, kTxfe = 1u << 7;
constexpr uint32_t kPktOutData = 2u, kPktOutDone = 3u, kPktSetupDone = 4u, kPktSetupData = 6u;

uint32_t rx_status(uint32_t ep, uint32_t bytes, uint32_t pktsts) { return ep | (bytes << 4) | (pktsts << 17); }

std::vector<uint32_t> to_words(std::span<const uint8_t> data) {
  std::vector<uint32_t> words((data.size() + 3) / 4, 0u);
  for (size_t i = 0; i < data.size(); ++i) words[i / 4] |= static_cast<uint32_t>(data[i]) << (8 * (i % 4));
  return words;
}

// Control register write: the write-only action bits act, the rest is stored.
uint32_t control_write(uint32_t old, uint32_t value, bool& disabled) {
  uint32_t ctl = (old & (kNaksts | kEpena)) | (value & ~(kSd0pid | kSnak | kCnak | kEpdis | kNaksts | kEpena));
  if (value & kEpena) ctl |= kEpena;
  if (value & kSnak) ctl |= kNaksts;
  if (value & kCnak) ctl &= ~kNaksts;
  disabled = (value & kEpdis) && (old & kEpena);
  if (disabled) ctl = (ctl & ~kEpena) | kNaksts;
  return ctl;
}

// DxEPCTL / DxEPINT / DxEPTSIZ of one endpoint (`reg`: offset in its 0x20-byte block).
bool endpoint_write(uint32_t reg, uint32_t v, uint32_t& ctl, uint32_t& intr, uint32_t& tsiz) {
  bool disabled = false;
  switch (reg) {
    case 0x00:
      ctl = control_write(ctl, v, disabled);
      if (disabled) intr |= kEpdisd;
      return true;
    case 0x08: intr &= ~v; return true;  // rc_w1
    case 0x10: tsiz = v; return true;
    default: return false;
  }
}

}  // namespace

void OtgFs::reset() {
  const uint64_t disconnects = disconnects_ + (connected() ? 1u : 0u);
  *this = OtgFs{};
  gusbcfg_ = 0x00000A00u;
  grxfsiz_ = 0x200u;
  dieptxf_[0] = 0x02000200u;
  disconnects_ = disconnects;
}

bool OtgFs::write(uint32_t offset, uint32_t v) {
  const bool was_connected = connected();
  const bool known = write_register(offset, v);
  if (was_connected && !connected()) ++disconnects_;  // the pull-up went off (SDIS, power down)
  return known;
}

uint32_t OtgFs::rx_words() const {
  uint32_t n = 0;
  for (const auto& e : rx_) n += static_cast<uint32_t>(e.words.size()) + 1u;
  return n;
}

uint32_t OtgFs::tx_depth(uint32_t ep) const { return dieptxf_[ep] >> 16; }

uint32_t OtgFs::daint() const {
  uint32_t d = 0;
  for (uint32_t n = 0; n < 4; ++n) {
    if (in_[n].intr & (diepmsk_ | kTxfe) & ~kTxfe) d |= 1u << n;
    if (out_[n].intr & doepmsk_) d |= 1u << (16 + n);
  }
  return d;
}

uint32_t OtgFs::gintsts() const {
  uint32_t s = gintsts_;
  if (!rx_.empty()) s |= kRxflvl;
  const uint32_t d = daint() & daintmsk_;
  if (d & 0xFFFFu) s |= kIepint;
  if (d >> 16) s |= kOepint;
  return s;
}

bool OtgFs::irq() const { return (gahbcfg_ & 1u) && (gintsts() & gintmsk_) != 0; }

bool OtgFs::connected() const {
  return (gusbcfg_ & (1u << 30)) && (gccfg_ & (1u << 16)) && !(dctl_ & (1u << 1));
}

void OtgFs::flush_tx(uint32_t number) {
  for (uint32_t n = 0; n < 4; ++n) {
    if (number == 0x10u || number == n) in_[n].fifo.clear();
  }
}

bool OtgFs::read(uint32_t offset, uint32_t& v) {
  if (offset >= 0x1000u && offset < 0x2000u) {  // FIFO 0 window: RX data of the popped entry
    v = 0;
    if (reading_ && read_index_ < reading_->words.size()) v = reading_->words[read_index_++];
    return true;
  }
  if (offset >= 0x900u && offset < 0x980u) {
    const InEp& e = in_[(offset - 0x900u) / 0x20u];
    switch (offset % 0x20u) {
      case 0x00: v = e.ctl; return true;
      case 0x08: v = e.intr | (e.fifo.empty() ? kTxfe : 0u); return true;
      case 0x10: v = e.tsiz; return true;
      case 0x18: v = tx_depth((offset - 0x900u) / 0x20u) - static_cast<uint32_t>(e.fifo.size()); return true;
      default: return false;
    }
  }
  if (offset >= 0xB00u && offset < 0xB80u) {
    const OutEp& e = out_[(offset - 0xB00u) / 0x20u];
    switch (offset % 0x20u) {
      case 0x00: v = e.ctl; return true;
      case 0x08: v = e.intr; return true;
      case 0x10: v = e.tsiz; return true;
      default: return false;
    }
  }
  switch (offset) {
    case 0x000: v = 0x000D0000u; return true;  // GOTGCTL: B-session valid (no VBUS sensing)
    case 0x008: v = gahbcfg_; return true;
    case 0x00C: v = gusbcfg_; return true;
    case 0x010: v = 1u << 31; return true;  // GRSTCTL: AHB idle, resets and flushes done at once
    case 0x014: v = gintsts(); return true;
    case 0x018: v = gintmsk_; return true;
    case 0x020:  // GRXSTSP: pop
      reading_.reset();
      read_index_ = 0;
      v = 0;
      if (rx_.empty()) return true;
      reading_ = std::move(rx_.front());
      rx_.pop_front();
      v = reading_->status;
      if (reading_->done_flag) {
        OutEp& e = out_[reading_->done_ep];
        e.intr |= reading_->done_flag;
        e.ctl = (e.ctl & ~kEpena) | kNaksts;
      }
      return true;
    case 0x024: v = grxfsiz_; return true;
    case 0x028: v = dieptxf_[0]; return true;
    case 0x038: v = gccfg_; return true;
    case 0x03C: v = 0x00001200u; return true;  // CID
    case 0x104: case 0x108: case 0x10C: v = dieptxf_[(offset - 0x100u) / 4u]; return true;
    case 0x800: v = dcfg_; return true;
    case 0x804: v = dctl_; return true;
    case 0x808: v = (suspended_ ? 1u : 0u) | (3u << 1) | ((frame_ & 0x3FFFu) << 8); return true;
    case 0x810: v = diepmsk_; return true;
    case 0x814: v = doepmsk_; return true;
    case 0x818: v = daint(); return true;
    case 0x81C: v = daintmsk_; return true;
    case 0xE00: v = pcgcctl_; return true;
    default: return false;
  }
}

bool OtgFs::write_register(uint32_t offset, uint32_t v) {
  if (offset >= 0x2000u && offset < 0x5000u) {  // FIFO 1..3 push (TX)
    InEp& e = in_[(offset - 0x1000u) / 0x1000u];
    if (e.fifo.size() < tx_depth((offset - 0x1000u) / 0x1000u)) e.fifo.push_back(v);
    return true;
  }
  if (offset >= 0x1000u && offset < 0x2000u) {
    if (in_[0].fifo.size() < tx_depth(0)) in_[0].fifo.push_back(v);
    return true;
  }
  if (offset >= 0x900u && offset < 0x980u) {
    InEp& e = in_[(offset - 0x900u) / 0x20u];
    return endpoint_write(offset % 0x20u, v, e.ctl, e.intr, e.tsiz);
  }
  if (offset >= 0xB00u && offset < 0xB80u) {
    OutEp& e = out_[(offset - 0xB00u) / 0x20u];
    return endpoint_write(offset % 0x20u, v, e.ctl, e.intr, e.tsiz);
  }
  switch (offset) {
    case 0x008: gahbcfg_ = v; return true;
    case 0x00C: gusbcfg_ = v; return true;
    case 0x010:
      if (v & 1u) {  // core soft reset: the core's state machines and interrupts, not the configuration
        gintsts_ = 0;
        rx_.clear();
        reading_.reset();
        flush_tx(0x10u);
      }
      if (v & (1u << 4)) { rx_.clear(); reading_.reset(); }
      if (v & (1u << 5)) flush_tx((v >> 6) & 0x1Fu);
      return true;
    case 0x014: gintsts_ &= ~(v & kGintstsClearable); return true;
    case 0x018: gintmsk_ = v; return true;
    case 0x024: grxfsiz_ = v; return true;
    case 0x028: dieptxf_[0] = v; return true;
    case 0x038: gccfg_ = v; return true;
    case 0x104: case 0x108: case 0x10C: dieptxf_[(offset - 0x100u) / 4u] = v; return true;
    case 0x800: dcfg_ = v; return true;
    case 0x804: dctl_ = v & ~((1u << 7) | (1u << 8) | (1u << 9) | (1u << 10)); return true;  // SGINAK.. are actions
    case 0x810: diepmsk_ = v; return true;
    case 0x814: doepmsk_ = v; return true;
    case 0x818: return true;  // DAINT is read-only (cleared through the endpoint registers)
    case 0x81C: daintmsk_ = v; return true;
    case 0xE00: pcgcctl_ = v; return true;
    default: return false;
  }
}

const char* OtgFs::register_name(uint32_t offset) {
  if (offset >= 0x1000u && offset < 0x5000u) return "FIFO";
  if (offset >= 0x900u && offset < 0x980u) {
    static const char* const names[] = {"DIEPCTL", "?", "DIEPINT", "?", "DIEPTSIZ", "?", "DTXFSTS", "?"};
    return names[(offset % 0x20u) / 4u];
  }
  if (offset >= 0xB00u && offset < 0xB80u) {
    static const char* const names[] = {"DOEPCTL", "?", "DOEPINT", "?", "DOEPTSIZ", "?", "?", "?"};
    return names[(offset % 0x20u) / 4u];
  }
  switch (offset) {
    case 0x000: return "GOTGCTL";
    case 0x008: return "GAHBCFG";
    case 0x00C: return "GUSBCFG";
    case 0x010: return "GRSTCTL";
    case 0x014: return "GINTSTS";
    case 0x018: return "GINTMSK";
    case 0x020: return "GRXSTSP";
    case 0x024: return "GRXFSIZ";
    case 0x028: return "DIEPTXF0";
    case 0x038: return "GCCFG";
    case 0x03C: return "CID";
    case 0x104: case 0x108: case 0x10C: return "DIEPTXF";
    case 0x800: return "DCFG";
    case 0x804: return "DCTL";
    case 0x808: return "DSTS";
    case 0x810: return "DIEPMSK";
    case 0x814: return "DOEPMSK";
    case 0x818: return "DAINT";
    case 0x81C: return "DAINTMSK";
    case 0xE00: return "PCGCCTL";
    default: return "?";
  }
}

void OtgFs::bus_reset() {
  suspended_ = false;
  gintsts_ |= kUsbrst | kEnumdne;
  dcfg_ &= ~(0x7Fu << 4);
  for (auto& e : in_) e.ctl &= ~kStall;
  for (auto& e : out_) e.ctl &= ~kStall;
}

void OtgFs::sof() {
  if (suspended_) return;
  frame_ = (frame_ + 1u) & 0x3FFFu;
  gintsts_ |= kSof;
}

void OtgFs::suspend() {
  suspended_ = true;
  gintsts_ |= kUsbsusp;
}

void OtgFs::resume() {
  suspended_ = false;
  gintsts_ |= kWkupint;
}

void OtgFs::setup(std::span<const uint8_t, 8> packet) {
  in_[0].ctl &= ~kStall;
  out_[0].ctl &= ~kStall;
  rx_.push_back({rx_status(0, 8, kPktSetupData), to_words(packet), 0, 0});
  rx_.push_back({rx_status(0, 0, kPktSetupDone), {}, 0, kStup});
}

OtgFs::Handshake OtgFs::out(uint32_t ep, std::span<const uint8_t> data) {
  OutEp& e = out_[ep];
  if (e.ctl & kStall) return Handshake::kStall;
  if (!(e.ctl & kEpena) || (e.ctl & kNaksts)) return Handshake::kNak;
  if (rx_words() + 2u + (data.size() + 3u) / 4u > (grxfsiz_ & 0xFFFFu)) return Handshake::kNak;
  rx_.push_back({rx_status(ep, static_cast<uint32_t>(data.size()), kPktOutData), to_words(data), 0, 0});
  rx_.push_back({rx_status(ep, 0, kPktOutDone), {}, ep, kXfrc});
  e.ctl &= ~kEpena;  // one packet per transfer (the firmware arms PKTCNT = 1)
  e.ctl |= kNaksts;
  return Handshake::kAck;
}

OtgFs::Handshake OtgFs::in(uint32_t ep, std::vector<uint8_t>& data) {
  InEp& e = in_[ep];
  data.clear();
  if (e.ctl & kStall) return Handshake::kStall;
  if (!(e.ctl & kEpena) || (e.ctl & kNaksts)) return Handshake::kNak;
  const uint32_t mps = ep == 0 ? 64u >> (e.ctl & 3u) : (e.ctl & 0x7FFu);
  const uint32_t size_mask = ep == 0 ? 0x7Fu : 0x7FFFFu;
  const uint32_t remaining = e.tsiz & size_mask;
  const uint32_t bytes = std::min(remaining, mps);
  if (e.fifo.size() < (bytes + 3u) / 4u) return Handshake::kNak;  // data not written yet
  for (uint32_t i = 0; i < (bytes + 3u) / 4u; ++i) {
    const uint32_t w = e.fifo.front();
    e.fifo.pop_front();
    for (uint32_t k = 0; k < 4 && 4 * i + k < bytes; ++k) data.push_back(static_cast<uint8_t>(w >> (8 * k)));
  }
  const uint32_t packets = ((e.tsiz >> 19) & 0x3FFu);
  const uint32_t left = remaining - bytes;
  e.tsiz = (e.tsiz & ~(size_mask | (0x3FFu << 19))) | left | ((packets > 0 ? packets - 1 : 0) << 19);
  if (packets <= 1 || left == 0) {
    e.ctl &= ~kEpena;
    e.intr |= kXfrc;
  }
  return Handshake::kAck;
}

}  // namespace cathbox::emu
