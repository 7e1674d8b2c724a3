// The emulated STM32 ROM DfuSe bootloader on its own: the DFU state machine, DfuSe commands,
// flash rules and the errors the ROM reports.
#include <gtest/gtest.h>

#include <array>

#include "emu/dfu_bootloader.hpp"
#include "protocol/cbx_bytes.h"
#include "protocol/cbx_usb_requests.h"

namespace cathbox::emu {
namespace {

class Rom : public ::testing::Test {
 protected:
  FlashMemory flash;
  DfuBootloader rom{flash};
  uint64_t now_us = 0;
  std::vector<uint8_t> reply;

  bool out(uint8_t request, uint16_t value, std::vector<uint8_t> data = {}) {
    const cbx_usb_setup s{CBX_DFU_OUT_TYPE, request, value, 0, static_cast<uint16_t>(data.size())};
    return rom.control(s, data, now_us, reply);
  }
  bool in(uint8_t request, uint16_t value, uint16_t length) {
    const cbx_usb_setup s{CBX_DFU_IN_TYPE, request, value, 0, length};
    return rom.control(s, {}, now_us, reply);
  }
  // GETSTATUS; returns {status, state, poll_ms}.
  std::array<uint32_t, 3> status() {
    EXPECT_TRUE(in(CBX_DFU_GETSTATUS, 0, 6));
    EXPECT_EQ(reply.size(), 6u);
    return {reply[0], reply[4], cbx_get_u24(reply.data() + 1)};
  }
  // Runs a DNLOAD to completion, honouring bwPollTimeout.
  std::array<uint32_t, 3> finish() {
    auto s = status();
    while (s[1] == CBX_DFU_DNBUSY) {
      now_us += uint64_t{s[2]} * 1000u;
      s = status();
    }
    return s;
  }
  static std::vector<uint8_t> command(uint8_t code, uint32_t address) {
    std::vector<uint8_t> cmd{code, 0, 0, 0, 0};
    cbx_put_u32(cmd.data() + 1, address);
    return cmd;
  }
};

TEST_F(Rom, EraseWriteReadBack) {
  ASSERT_TRUE(out(CBX_DFU_DNLOAD, 0, command(CBX_DFUSE_ERASE, 0x08004000u)));
  const auto busy = status();
  EXPECT_EQ(busy[1], CBX_DFU_DNBUSY);
  EXPECT_EQ(busy[2], 250u);  // 16 KiB sector erase time
  EXPECT_EQ(status()[1], CBX_DFU_DNBUSY) << "still busy before the poll timeout";
  EXPECT_EQ(finish()[1], CBX_DFU_DNLOAD_IDLE);
  ASSERT_TRUE(out(CBX_DFU_DNLOAD, 0, command(CBX_DFUSE_SET_ADDRESS, 0x08004000u)));
  EXPECT_EQ(finish()[1], CBX_DFU_DNLOAD_IDLE);
  ASSERT_TRUE(out(CBX_DFU_DNLOAD, 3, std::vector<uint8_t>(100, 0x5A)));  // block 3: +2048
  EXPECT_EQ(finish()[0], CBX_DFU_OK);
  std::array<uint8_t, 100> back{};
  ASSERT_TRUE(flash.read(0x08004800u, back));
  EXPECT_EQ(back[99], 0x5A);
  ASSERT_TRUE(out(CBX_DFU_ABORT, 0));
  ASSERT_TRUE(in(CBX_DFU_UPLOAD, 3, 100));
  EXPECT_EQ(reply, std::vector<uint8_t>(100, 0x5A));
  EXPECT_EQ(status()[1], CBX_DFU_UPLOAD_IDLE);
}

TEST_F(Rom, WritingUnerasedFlashIsAnErrorUntilCleared) {
  flash.load(0x08000000u, std::vector<uint8_t>(16, 0x00));
  ASSERT_TRUE(out(CBX_DFU_DNLOAD, 2, std::vector<uint8_t>(16, 0x11)));
  const auto s = finish();
  EXPECT_EQ(s[0], CBX_DFU_ERR_WRITE);
  EXPECT_EQ(s[1], CBX_DFU_ERROR);
  EXPECT_FALSE(out(CBX_DFU_DNLOAD, 2, std::vector<uint8_t>(16, 0x11))) << "stalls in dfuERROR";
  ASSERT_TRUE(out(CBX_DFU_CLRSTATUS, 0));
  EXPECT_EQ(status()[1], CBX_DFU_IDLE);
}

TEST_F(Rom, AddressesOutsideFlashAreRefused) {
  ASSERT_TRUE(out(CBX_DFU_DNLOAD, 0, command(CBX_DFUSE_SET_ADDRESS, 0x08080000u)));
  EXPECT_EQ(finish()[0], CBX_DFU_ERR_TARGET);
  ASSERT_TRUE(out(CBX_DFU_CLRSTATUS, 0));
  ASSERT_TRUE(out(CBX_DFU_DNLOAD, 0, command(CBX_DFUSE_ERASE, 0x20000000u)));
  EXPECT_EQ(finish()[0], CBX_DFU_ERR_TARGET);
}

TEST_F(Rom, UnsupportedRequestsStall) {
  EXPECT_FALSE(out(CBX_DFU_DNLOAD, 0, {CBX_DFUSE_ERASE}));  // mass erase is not emulated
  ASSERT_TRUE(out(CBX_DFU_CLRSTATUS, 0));
  EXPECT_FALSE(out(CBX_DFU_DNLOAD, 1, {1, 2, 3}));  // block 1 is unused
  ASSERT_TRUE(out(CBX_DFU_CLRSTATUS, 0));
  EXPECT_FALSE(out(CBX_DFU_DNLOAD, 0, {}));  // leave from dfuIDLE
  ASSERT_TRUE(out(CBX_DFU_CLRSTATUS, 0));
  EXPECT_FALSE(in(CBX_DFU_UPLOAD, 2, 4096));  // longer than wTransferSize
  EXPECT_FALSE(in(0x77, 0, 1));
}

TEST_F(Rom, AbortBeforeTheDownloadStatusStallsIntoError) {
  // DFU 1.1: dfuDNLOAD-SYNC takes only GETSTATUS and GETSTATE; anything else stalls into dfuERROR.
  flash.load(0x08004000u, std::vector<uint8_t>(16, 0x00));
  ASSERT_TRUE(out(CBX_DFU_DNLOAD, 0, command(CBX_DFUSE_ERASE, 0x08004000u)));
  EXPECT_EQ(rom.state(), CBX_DFU_DNLOAD_SYNC);
  EXPECT_FALSE(out(CBX_DFU_ABORT, 0));
  const auto s = status();
  EXPECT_EQ(s[0], CBX_DFU_ERR_STALLEDPKT);
  EXPECT_EQ(s[1], CBX_DFU_ERROR);
  std::array<uint8_t, 16> kept{};
  ASSERT_TRUE(flash.read(0x08004000u, kept));
  EXPECT_EQ(kept[0], 0x00) << "the erase never ran";
  ASSERT_TRUE(out(CBX_DFU_CLRSTATUS, 0));
  EXPECT_EQ(status()[1], CBX_DFU_IDLE);
}

TEST_F(Rom, LeaveManifestsAndAsksForAReset) {
  ASSERT_TRUE(out(CBX_DFU_DNLOAD, 0, command(CBX_DFUSE_SET_ADDRESS, 0x08000000u)));
  finish();
  ASSERT_TRUE(out(CBX_DFU_DNLOAD, 0, {}));
  EXPECT_FALSE(rom.leave_requested());
  EXPECT_EQ(status()[1], CBX_DFU_MANIFEST);
  EXPECT_TRUE(rom.leave_requested());
}

TEST_F(Rom, AnnouncesItsLayoutAsAStringDescriptor) {
  const cbx_usb_setup s{0x80, 0x06, 0x0304, 0x0409, 255};
  ASSERT_TRUE(rom.control(s, {}, now_us, reply));
  ASSERT_GT(reply.size(), 2u);
  EXPECT_EQ(reply[0], reply.size());
  EXPECT_EQ(reply[1], 0x03);
  std::string text;
  for (size_t i = 2; i < reply.size(); i += 2) text.push_back(static_cast<char>(reply[i]));
  EXPECT_EQ(text, flash.layout_name());
}

TEST(FlashMemory, ApplicationValidNeedsAVectorTable) {
  FlashMemory flash;
  EXPECT_FALSE(flash.application_valid());  // erased
  const std::vector<uint8_t> vectors = {0x00, 0x80, 0x00, 0x20, 0x01, 0x02, 0x00, 0x08};
  flash.load(FlashMemory::kBase, vectors);
  EXPECT_TRUE(flash.application_valid());
  flash.erase_sector(0);
  EXPECT_FALSE(flash.application_valid());
}

}  // namespace
}  // namespace cathbox::emu
