#include "device/dfuse_client.hpp"

#include <algorithm>
#include <array>
#include <cstdio>

#include "device/dfuse_layout.hpp"
#include "protocol/cbx_bytes.h"
#include "protocol/cbx_usb_requests.h"

namespace cathbox::device {
namespace {

const char* dfu_status_name(uint8_t status) {
  switch (status) {
    case CBX_DFU_OK: return "OK";
    case CBX_DFU_ERR_TARGET: return "errTARGET (address or command not supported)";
    case CBX_DFU_ERR_WRITE: return "errWRITE";
    case CBX_DFU_ERR_ERASE: return "errERASE";
    case CBX_DFU_ERR_VERIFY: return "errVERIFY";
    case CBX_DFU_ERR_ADDRESS: return "errADDRESS (out of range or not erased)";
    case CBX_DFU_ERR_STALLEDPKT: return "errSTALLEDPKT";
    default: return "error";
  }
}

}  // namespace

Result<DfuStatus> DfuseClient::get_status() {
  std::array<uint8_t, CBX_DFU_STATUS_SIZE> raw{};
  auto got = usb_.control_in({CBX_DFU_IN_TYPE, CBX_DFU_GETSTATUS, 0, 0}, raw);
  if (!got) return got.error();
  if (got.value() != raw.size()) return make_error(Errc::kDeviceError, "DFU GETSTATUS returned " + std::to_string(got.value()) + " bytes, not 6");
  DfuStatus s;
  s.status = raw[0];
  s.poll_timeout_ms = cbx_get_u24(raw.data() + 1);
  s.state = raw[4];
  return s;
}

Status DfuseClient::ensure_idle() {
  auto s = get_status();
  if (!s) return s.error();
  // An operation interrupted earlier (a pulled cable) may still be running: let it finish.
  for (int polls = 0; polls < 100 && (s.value().state == CBX_DFU_DNBUSY || s.value().state == CBX_DFU_DNLOAD_SYNC); ++polls) {
    usb_.delay(uint64_t{std::max<uint32_t>(s.value().poll_timeout_ms, 1u)} * 1000u);
    s = get_status();
    if (!s) return s.error();
  }
  if (s.value().state == CBX_DFU_ERROR) {
    auto cleared = usb_.control_out({CBX_DFU_OUT_TYPE, CBX_DFU_CLRSTATUS, 0, 0}, {});
    if (!cleared) return cleared;
    s = get_status();
    if (!s) return s.error();
  }
  if (s.value().state != CBX_DFU_IDLE) {
    auto aborted = usb_.control_out({CBX_DFU_OUT_TYPE, CBX_DFU_ABORT, 0, 0}, {});
    if (!aborted) return aborted;
    s = get_status();
    if (!s) return s.error();
  }
  if (s.value().state != CBX_DFU_IDLE) {
    return make_error(Errc::kDeviceError, "bootloader does not return to dfuIDLE (state " + std::to_string(s.value().state) + ")");
  }
  return Ok{};
}

Status DfuseClient::wait_state(uint8_t want, const char* what) {
  // DNLOAD-SYNC -> (GETSTATUS starts the operation) -> DNBUSY for bwPollTimeout -> want.
  for (int polls = 0; polls < 1000; ++polls) {
    auto s = get_status();
    if (!s) return s.error();
    if (s.value().status != CBX_DFU_OK || s.value().state == CBX_DFU_ERROR) {
      return make_error(Errc::kDeviceError, std::string(what) + ": bootloader reports " + dfu_status_name(s.value().status));
    }
    if (s.value().state == want) return Ok{};
    if (s.value().poll_timeout_ms > 0) usb_.delay(uint64_t{s.value().poll_timeout_ms} * 1000u);
  }
  return make_error(Errc::kTimeout, std::string(what) + ": bootloader stays busy");
}

Status DfuseClient::dnload(uint16_t block, std::span<const uint8_t> data) {
  return usb_.control_out({CBX_DFU_OUT_TYPE, CBX_DFU_DNLOAD, block, 0}, data);
}

Status DfuseClient::command(uint8_t code, uint32_t address, const char* what) {
  std::array<uint8_t, 5> cmd{code};
  cbx_put_u32(cmd.data() + 1, address);
  auto sent = dnload(0, cmd);
  if (!sent) return make_error(sent.error().code, std::string(what) + " " + hex_address(address) + ": " + sent.error().message);
  return wait_state(CBX_DFU_DNLOAD_IDLE, (std::string(what) + " " + hex_address(address)).c_str());
}

Status DfuseClient::set_address(uint32_t address) { return command(CBX_DFUSE_SET_ADDRESS, address, "set address"); }

Status DfuseClient::erase(uint32_t sector_address) { return command(CBX_DFUSE_ERASE, sector_address, "erase"); }

Status DfuseClient::write(uint32_t address, std::span<const uint8_t> data) {
  for (size_t off = 0; off < data.size(); off += transfer_size_) {
    const size_t n = std::min<size_t>(transfer_size_, data.size() - off);
    auto at = set_address(address + static_cast<uint32_t>(off));
    if (!at) return at;
    auto sent = dnload(2, data.subspan(off, n));
    if (!sent) return sent;
    auto done = wait_state(CBX_DFU_DNLOAD_IDLE, ("write at " + hex_address(address + static_cast<uint32_t>(off))).c_str());
    if (!done) return done;
  }
  return Ok{};
}

Result<std::vector<uint8_t>> DfuseClient::read(uint32_t address, size_t length) {
  auto at = set_address(address);
  if (!at) return at.error();
  auto idle = ensure_idle();  // UPLOAD starts from dfuIDLE; the address pointer stays
  if (!idle) return idle.error();
  std::vector<uint8_t> out(length);
  for (size_t off = 0, block = 2; off < length; off += transfer_size_, ++block) {
    const size_t n = std::min<size_t>(transfer_size_, length - off);
    auto got = usb_.control_in({CBX_DFU_IN_TYPE, CBX_DFU_UPLOAD, static_cast<uint16_t>(block), 0},
                               std::span<uint8_t>(out).subspan(off, n));
    if (!got) return got.error();
    if (got.value() != n) return make_error(Errc::kDeviceError, "upload at " + hex_address(address + static_cast<uint32_t>(off)) + " returned " + std::to_string(got.value()) + " bytes");
  }
  auto back = ensure_idle();
  if (!back) return back.error();
  return out;
}

Status DfuseClient::leave(uint32_t address) {
  auto at = set_address(address);
  if (!at) return at;
  auto sent = dnload(0, {});
  if (!sent) return sent;
  // The bootloader answers this GETSTATUS in dfuMANIFEST and then resets into the application;
  // the connection may drop right after, which is success.
  auto s = get_status();
  if (!s && s.error().code != Errc::kDisconnected) return s.error();
  if (s && s.value().state != CBX_DFU_MANIFEST) {
    return make_error(Errc::kDeviceError, "leave: bootloader in state " + std::to_string(s.value().state) + ", not dfuMANIFEST");
  }
  return Ok{};
}

}  // namespace cathbox::device
