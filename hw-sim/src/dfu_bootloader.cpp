#include "emu/dfu_bootloader.hpp"

#include "protocol/cbx_bytes.h"
#include "protocol/cbx_usb_requests.h"

namespace cathbox::emu {
namespace {

constexpr uint32_t kProgramPerBlock_ms = 9;  // 2 KiB at ~16 us per 32-bit word, rounded up
constexpr uint8_t kStringIndexAlt0 = 4;     // iInterface of alternate setting 0

}  // namespace

void DfuBootloader::reset() {
  state_ = CBX_DFU_IDLE;
  status_ = CBX_DFU_OK;
  pointer_ = FlashMemory::kBase;
  op_ = Op::kNone;
  leave_ = false;
  busy_until_us_ = 0;
}

void DfuBootloader::fail(uint8_t status) {
  state_ = CBX_DFU_ERROR;
  status_ = status;
  op_ = Op::kNone;
}

bool DfuBootloader::control(const cbx_usb_setup& setup, std::span<const uint8_t> out, uint64_t now_us,
                            std::vector<uint8_t>& reply) {
  reply.clear();
  if (setup.request_type == 0x80 && setup.request == 0x06) {  // GET_DESCRIPTOR
    if (setup.value != (0x0300u | kStringIndexAlt0)) return false;
    const std::string name = flash_.layout_name();
    reply.push_back(static_cast<uint8_t>(2 + 2 * name.size()));
    reply.push_back(0x03);
    for (const char c : name) {
      reply.push_back(static_cast<uint8_t>(c));
      reply.push_back(0);
    }
    if (reply.size() > setup.length) reply.resize(setup.length);
    return true;
  }
  const bool in = setup.request_type == CBX_DFU_IN_TYPE;
  if (!in && setup.request_type != CBX_DFU_OUT_TYPE) return false;
  switch (setup.request) {
    case CBX_DFU_GETSTATUS:
      if (!in || setup.length < CBX_DFU_STATUS_SIZE) return false;
      get_status(now_us, reply);
      return true;
    case CBX_DFU_GETSTATE:
      if (!in || setup.length < 1) return false;
      reply.push_back(state_);
      return true;
    case CBX_DFU_CLRSTATUS:
      if (in || state_ != CBX_DFU_ERROR) {
        fail(CBX_DFU_ERR_STALLEDPKT);
        return false;
      }
      state_ = CBX_DFU_IDLE;
      status_ = CBX_DFU_OK;
      return true;
    case CBX_DFU_ABORT:
      if (in || state_ == CBX_DFU_ERROR || state_ == CBX_DFU_DNBUSY || state_ == CBX_DFU_MANIFEST) {
        return false;
      }
      if (state_ == CBX_DFU_DNLOAD_SYNC || state_ == CBX_DFU_MANIFEST_SYNC) {
        fail(CBX_DFU_ERR_STALLEDPKT);  // these states take only GETSTATUS and GETSTATE
        return false;
      }
      state_ = CBX_DFU_IDLE;
      op_ = Op::kNone;
      return true;
    case CBX_DFU_DNLOAD:
      if (in || !dnload(setup.value, out)) {
        fail(CBX_DFU_ERR_STALLEDPKT);
        return false;
      }
      return true;
    case CBX_DFU_UPLOAD:
      if (!in || !upload(setup.value, setup.length, reply)) {
        if (state_ != CBX_DFU_ERROR) fail(CBX_DFU_ERR_STALLEDPKT);
        return false;
      }
      return true;
    default:
      return false;
  }
}

void DfuBootloader::get_status(uint64_t now_us, std::vector<uint8_t>& reply) {
  uint32_t poll_ms = 0;
  if (state_ == CBX_DFU_DNLOAD_SYNC) {
    poll_ms = execute();
    if (state_ != CBX_DFU_ERROR) {
      state_ = CBX_DFU_DNBUSY;
      busy_until_us_ = now_us + uint64_t{poll_ms} * 1000u;
    }
  } else if (state_ == CBX_DFU_DNBUSY) {
    if (now_us >= busy_until_us_) {
      state_ = CBX_DFU_DNLOAD_IDLE;
    } else {
      poll_ms = static_cast<uint32_t>((busy_until_us_ - now_us + 999) / 1000);
    }
  } else if (state_ == CBX_DFU_MANIFEST_SYNC) {
    state_ = CBX_DFU_MANIFEST;
    leave_ = true;  // the ROM resets into the application after this status
  }
  reply = {status_, 0, 0, 0, state_, 0};
  cbx_put_u24(reply.data() + 1, poll_ms);
}

bool DfuBootloader::dnload(uint16_t block, std::span<const uint8_t> data) {
  if (state_ != CBX_DFU_IDLE && state_ != CBX_DFU_DNLOAD_IDLE) return false;
  if (data.empty()) {
    if (state_ != CBX_DFU_DNLOAD_IDLE) return false;
    state_ = CBX_DFU_MANIFEST_SYNC;
    op_ = Op::kLeave;
    return true;
  }
  if (block == 0) {
    if (data[0] == CBX_DFUSE_SET_ADDRESS && data.size() == 5) {
      op_ = Op::kSetAddress;
    } else if (data[0] == CBX_DFUSE_ERASE && data.size() == 5) {
      op_ = Op::kErase;
    } else {
      return false;  // mass erase, read unprotect, unknown: not emulated
    }
    op_address_ = cbx_get_u32(data.data() + 1);
  } else if (block >= 2 && data.size() <= kTransferSize) {
    op_ = Op::kWrite;
    op_address_ = pointer_ + static_cast<uint32_t>(block - 2u) * kTransferSize;
    op_data_.assign(data.begin(), data.end());
  } else {
    return false;
  }
  state_ = CBX_DFU_DNLOAD_SYNC;
  return true;
}

uint32_t DfuBootloader::execute() {
  const Op op = op_;
  op_ = Op::kNone;
  switch (op) {
    case Op::kSetAddress:
      if (!flash_.contains(op_address_, 1)) {
        fail(CBX_DFU_ERR_TARGET);
        return 0;
      }
      pointer_ = op_address_;
      return 0;
    case Op::kErase: {
      const int sector = flash_.sector_at(op_address_);
      if (sector < 0) {
        fail(CBX_DFU_ERR_TARGET);
        return 0;
      }
      flash_.erase_sector(sector);
      return flash_.sectors()[static_cast<size_t>(sector)].erase_ms;
    }
    case Op::kWrite:
      if (!flash_.contains(op_address_, op_data_.size())) {
        fail(CBX_DFU_ERR_ADDRESS);
        return 0;
      }
      if (!flash_.program(op_address_, op_data_)) {
        fail(CBX_DFU_ERR_WRITE);  // target not erased
        return 0;
      }
      return kProgramPerBlock_ms;
    case Op::kLeave:
    case Op::kNone:
      return 0;
  }
  return 0;
}

bool DfuBootloader::upload(uint16_t block, uint16_t length, std::vector<uint8_t>& reply) {
  if (state_ != CBX_DFU_IDLE && state_ != CBX_DFU_UPLOAD_IDLE) return false;
  if (block == 0) {
    reply = {CBX_DFUSE_GET_COMMANDS, CBX_DFUSE_SET_ADDRESS, CBX_DFUSE_ERASE, CBX_DFUSE_READ_UNPROTECT};
    if (reply.size() > length) reply.resize(length);
  } else if (block >= 2 && length <= kTransferSize) {
    const uint32_t address = pointer_ + static_cast<uint32_t>(block - 2u) * kTransferSize;
    reply.resize(length);
    if (!flash_.read(address, reply)) {
      reply.clear();
      fail(CBX_DFU_ERR_ADDRESS);
      return false;
    }
  } else {
    return false;
  }
  state_ = CBX_DFU_UPLOAD_IDLE;
  return true;
}

}  // namespace cathbox::emu
