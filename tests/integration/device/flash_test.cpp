// Flashing end to end: `cathbox flash`'s code path (BoxClient -> enter bootloader -> DfuSe over
// the socket -> the emulated STM32 ROM bootloader and its flash) in virtual time.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "device/dfu_file.hpp"
#include "device/flasher.hpp"
#include "device/socket_transport.hpp"
#include "protocol/cbx_bytes.h"
#include "protocol/cbx_image_info.h"
#include "protocol/cbx_usb_requests.h"
#include "emu_world.hpp"

namespace cathbox::testing {
namespace {

using device::DfuImage;
using device::Errc;
using device::Flasher;

DfuImage make_image(size_t size, uint16_t version = 0x0100, const char* target = "cathbox stm32f411",
                    bool with_info = true) {
  DfuImage image;
  image.bcd_device = version;
  image.vid = CBX_DFU_VID;
  image.pid = CBX_DFU_PID;
  image.target_name = target;
  device::DfuElement e;
  e.address = 0x08000000u;
  e.data.resize(size);
  std::mt19937 rng(42);
  for (auto& b : e.data) b = static_cast<uint8_t>(rng());
  const uint32_t sp = 0x20008000u;
  const uint32_t reset = 0x08000201u;
  cbx_put_u32(e.data.data(), sp);
  cbx_put_u32(e.data.data() + 4, reset);
  // The image info block (protocol/cbx_image_info.h) of the version being packed.
  if (with_info && size >= CBX_IMAGE_INFO_OFFSET + CBX_IMAGE_INFO_SIZE) {
    cbx_image_info info{};
    info.fw_major = static_cast<uint8_t>(version >> 8);
    info.fw_minor = static_cast<uint8_t>(version & 0xFF);
    info.fw_patch = 0;
    info.protocol_minor = CBX_PROTOCOL_MINOR;
    std::snprintf(info.board, sizeof info.board, "cathbox-emu");
    std::snprintf(info.build, sizeof info.build, "t-%04x", version);
    info.image_size = static_cast<uint32_t>(size);
    EXPECT_EQ(cbx_image_info_encode(&info, e.data.data() + CBX_IMAGE_INFO_OFFSET), CBX_OK);
  }
  image.elements.push_back(std::move(e));
  return image;
}

std::vector<uint8_t> flash_bytes(emu::Emulator& emu, size_t n) {
  std::vector<uint8_t> out(n);
  EXPECT_TRUE(emu.flash().read(emu::FlashMemory::kBase, out));
  return out;
}

// The application asks the box into its bootloader; returns a transport to the bootloader.
std::unique_ptr<device::SocketTransport> enter_bootloader(EmuWorld& world) {
  auto client = world.connect();
  EXPECT_TRUE(client->enter_bootloader().ok());
  world.advance(1000);
  auto dfu = device::SocketTransport::open(world.path(), world);
  if (!dfu) {
    ADD_FAILURE() << dfu.error().message;
    return nullptr;
  }
  EXPECT_EQ(dfu.value()->pid(), CBX_DFU_PID);
  return std::move(dfu.value());
}

// After a failed or refused image: the board is in the ROM bootloader and enumerates as it;
// returns a transport to it.
std::unique_ptr<device::SocketTransport> still_in_bootloader(EmuWorld& world) {
  world.advance(5000);
  EXPECT_EQ(world.emu().mode(), emu::BoardMode::kBootloader);
  auto again = device::SocketTransport::open(world.path(), world);
  if (!again) {
    ADD_FAILURE() << again.error().message;
    return nullptr;
  }
  EXPECT_EQ(again.value()->pid(), CBX_DFU_PID);
  return std::move(again.value());
}

// A cable that is pulled after `budget` control transfers.
class FlakyControl final : public device::ControlTransfer {
 public:
  FlakyControl(device::ControlTransfer& inner, int budget) : inner_(inner), budget_(budget) {}
  device::Status control_out(const device::UsbSetup& s, std::span<const uint8_t> d) override {
    if (--budget_ < 0) return device::make_error(Errc::kDisconnected, "cable pulled");
    return inner_.control_out(s, d);
  }
  device::Result<size_t> control_in(const device::UsbSetup& s, std::span<uint8_t> in) override {
    if (--budget_ < 0) return device::make_error(Errc::kDisconnected, "cable pulled");
    return inner_.control_in(s, in);
  }
  device::Result<std::string> alt_name(uint8_t alt) override { return inner_.alt_name(alt); }
  void delay(uint64_t us) override { inner_.delay(us); }
  std::string describe() const override { return "flaky " + inner_.describe(); }

 private:
  device::ControlTransfer& inner_;
  int budget_;
};

// Watches every DFU GETSTATUS: none may come before the bwPollTimeout of the previous answer
// that said dfuDNBUSY (DFU 1.1), and busy states are not polled in a spin.
class PollTimeoutWatch final : public device::ControlTransfer {
 public:
  PollTimeoutWatch(device::ControlTransfer& inner, device::Clock& clock) : inner_(inner), clock_(clock) {}
  device::Status control_out(const device::UsbSetup& s, std::span<const uint8_t> d) override { return inner_.control_out(s, d); }
  device::Result<size_t> control_in(const device::UsbSetup& s, std::span<uint8_t> in) override {
    const uint64_t asked_us = clock_.now_us();
    auto got = inner_.control_in(s, in);
    if (s.request != CBX_DFU_GETSTATUS || !got || got.value() != CBX_DFU_STATUS_SIZE) return got;
    ++statuses;
    if (asked_us < not_before_us) ++early;
    const uint32_t poll_ms = cbx_get_u24(in.data() + 1);
    busy_ms += in[4] == CBX_DFU_DNBUSY ? poll_ms : 0u;
    not_before_us = in[4] == CBX_DFU_DNBUSY ? clock_.now_us() + uint64_t{poll_ms} * 1000u : 0u;
    return got;
  }
  device::Result<std::string> alt_name(uint8_t alt) override { return inner_.alt_name(alt); }
  void delay(uint64_t us) override { inner_.delay(us); }
  std::string describe() const override { return inner_.describe(); }

  int statuses = 0;
  int early = 0;
  uint64_t busy_ms = 0;

 private:
  device::ControlTransfer& inner_;
  device::Clock& clock_;
  uint64_t not_before_us = 0;
};

TEST(Flash, GetStatusHonoursBwPollTimeout) {
  EmuWorld world;
  const DfuImage image = make_image(40 * 1024);  // sectors 0..2: 250 + 250 + 250 ms of erase
  auto dfu = enter_bootloader(world);
  ASSERT_TRUE(dfu);
  PollTimeoutWatch watch(*dfu, world);
  const uint64_t start = world.now_us();
  auto done = Flasher::flash(watch, image, {}, {});
  ASSERT_TRUE(done.ok()) << done.error().message;
  EXPECT_EQ(watch.early, 0) << "GETSTATUS sent before bwPollTimeout ran out";
  EXPECT_GE(watch.busy_ms, 750u);
  EXPECT_GE(world.now_us() - start, watch.busy_ms * 1000u);
  // Per operation: the status that starts it, at most a few while busy, the one that ends it.
  const int operations = 3 + 20 * 2;  // 3 erases, 20 blocks of 2 KiB each with its set-address
  EXPECT_LE(watch.statuses, operations * 3 + 10) << "busy states polled in a spin";
  std::printf("%d GETSTATUS for %d DfuSe operations, %llu ms busy announced\n", watch.statuses, operations,
              static_cast<unsigned long long>(watch.busy_ms));
}

TEST(Flash, GoodImageFlashesVerifiesAndTheBoxComesBack) {
  EmuWorld world;
  const DfuImage image = make_image(40 * 1024 + 123);  // sectors 0, 1 and 2
  // Through the file format, as `cathbox flash FILE` reads it.
  auto parsed = device::DfuFile::parse(device::DfuFile::write(image), "good.dfu");
  ASSERT_TRUE(parsed.ok()) << parsed.error().message;
  auto dfu = enter_bootloader(world);
  ASSERT_TRUE(dfu);
  EXPECT_EQ(world.emu().mode(), emu::BoardMode::kBootloader);
  const uint64_t start = world.now_us();
  auto done = Flasher::flash(*dfu, parsed.value(), {}, {});
  ASSERT_TRUE(done.ok()) << done.error().message;
  std::printf("flashed %zu bytes in %.2f s of virtual time (%zu sectors erased)\n", done.value().bytes_written,
              (world.now_us() - start) / 1e6, done.value().sectors_erased);
  EXPECT_EQ(done.value().sectors_erased, 3u);
  EXPECT_EQ(done.value().bytes_verified, image.total_bytes());
  EXPECT_EQ(flash_bytes(world.emu(), image.total_bytes()), image.elements[0].data);
  // The bootloader reset into the application, which enumerates again.
  dfu.reset();
  world.advance(1000);
  EXPECT_EQ(world.emu().mode(), emu::BoardMode::kApplication);
  auto client = world.connect();
  EXPECT_STREQ(client->device_info().board, "cathbox-emu");
}

TEST(Flash, CorruptAndTruncatedFilesAreRefusedBeforeAnythingIsErased) {
  auto bytes = device::DfuFile::write(make_image(4096));
  auto corrupt = bytes;
  corrupt[400] ^= 0x10;
  auto bad = device::DfuFile::parse(corrupt, "corrupt.dfu");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code, Errc::kBadImage);
  EXPECT_NE(bad.error().message.find("CRC"), std::string::npos) << bad.error().message;
  const std::vector<uint8_t> truncated(bytes.begin(), bytes.begin() + 3000);
  auto cut = device::DfuFile::parse(truncated, "cut.dfu");
  ASSERT_FALSE(cut.ok());
  EXPECT_NE(cut.error().message.find("cut.dfu: byte"), std::string::npos) << cut.error().message;
}

TEST(Flash, WrongTargetVersionOrLayoutIsRefusedInTheBootloaderBeforeErasing) {
  EmuWorld world;
  const auto before = flash_bytes(world.emu(), 64 * 1024);
  auto dfu = enter_bootloader(world);
  ASSERT_TRUE(dfu);
  DfuImage outside = make_image(1024);
  outside.elements.push_back({0x08080000u, std::vector<uint8_t>(16, 0)});
  DfuImage bad_stack = make_image(1024);
  bad_stack.elements[0].data[3] = 0x10;  // SP 0x10008000: CCM/other MCU
  const std::vector<std::pair<const char*, DfuImage>> refused = {
      {"target", make_image(1024, 0x0100, "cathbox stm32f401")},
      {"version", make_image(1024, 0x0200)},
      {"outside", outside},
      {"stack", bad_stack},
  };
  for (const auto& [what, image] : refused) {
    auto done = Flasher::flash(*dfu, image, {}, {});
    ASSERT_FALSE(done.ok()) << what;
    EXPECT_EQ(done.error().code, Errc::kBadImage) << what;
    EXPECT_NE(done.error().message.find("nothing erased"), std::string::npos) << done.error().message;
    std::printf("%s: %s\n", what, done.error().message.c_str());
  }
  EXPECT_EQ(flash_bytes(world.emu(), before.size()), before);
  EXPECT_EQ(world.emu().mode(), emu::BoardMode::kBootloader);
}

TEST(Flash, TruncatedTransferFailsSafelyAndTheBootloaderStaysReachable) {
  EmuWorld world;
  const DfuImage image = make_image(20 * 1024);
  auto dfu = enter_bootloader(world);
  ASSERT_TRUE(dfu);
  FlakyControl flaky(*dfu, 40);  // the cable goes after 40 control transfers (mid-download)
  auto broken = Flasher::flash(flaky, image, {}, {});
  ASSERT_FALSE(broken.ok());
  EXPECT_EQ(broken.error().code, Errc::kDisconnected);
  dfu.reset();
  // Still the bootloader: it enumerates again and a second attempt completes.
  auto again = still_in_bootloader(world);
  ASSERT_TRUE(again);
  std::printf("bootloader state after the pull: %d\n", world.emu().bootloader_state());
  auto done = Flasher::flash(*again, image, {}, {});
  ASSERT_TRUE(done.ok()) << done.error().message;
  EXPECT_EQ(flash_bytes(world.emu(), image.total_bytes()), image.elements[0].data);
}

TEST(Flash, BrokenImageNeedsTheBootStrapAndRecoversThroughIt) {
  // A board whose flash holds no bootable application does not enumerate; BOOT0 high and a
  // reset (what `cathbox flash --recover-gpio` drives) start the ROM bootloader.
  EmuWorld world;
  world.emu().flash().erase_sector(0);
  world.emu().reset();
  EXPECT_EQ(world.emu().mode(), emu::BoardMode::kNoFirmware);
  EXPECT_FALSE(device::SocketTransport::open(world.path(), world).ok());
  world.emu().set_boot0(true);
  world.emu().reset();
  auto dfu = device::SocketTransport::open(world.path(), world);
  ASSERT_TRUE(dfu.ok());
  EXPECT_EQ(dfu.value()->pid(), CBX_DFU_PID);
  ASSERT_TRUE(Flasher::flash(*dfu.value(), make_image(2048), {}, {}).ok());
  world.emu().set_boot0(false);
  world.emu().reset();
  EXPECT_EQ(world.emu().mode(), emu::BoardMode::kApplication);
}

TEST(Flash, TheBoxReportsTheVersionOfTheImageItRuns) {
  // The factory image says 1.0.0; after flashing 1.1 the box says 1.1.0 and the build of the
  // image (the emulated flash holds the image; the version is read from its info block).
  EmuWorld world;
  {
    auto before = world.connect();
    EXPECT_EQ(before->device_info().fw_major, 1);
    EXPECT_EQ(before->device_info().fw_minor, 0);
    EXPECT_STREQ(before->device_info().build, "factory");
  }
  auto dfu = enter_bootloader(world);
  ASSERT_TRUE(dfu);
  ASSERT_TRUE(Flasher::flash(*dfu, make_image(4096, 0x0101), {}, {}).ok());
  dfu.reset();
  world.advance(5000);
  ASSERT_EQ(world.emu().mode(), emu::BoardMode::kApplication);
  auto after = world.connect();
  EXPECT_EQ(after->device_info().fw_major, 1);
  EXPECT_EQ(after->device_info().fw_minor, 1);
  EXPECT_EQ(after->device_info().fw_patch, 0);
  EXPECT_STREQ(after->device_info().build, "t-0101");
}

TEST(Flash, AnImageWithoutAnInfoBlockLeavesTheBoxInTheBootloader) {
  EmuWorld world;
  auto dfu = enter_bootloader(world);
  ASSERT_TRUE(dfu);
  ASSERT_TRUE(Flasher::flash(*dfu, make_image(4096, 0x0101, "cathbox stm32f411", false), {}, {}).ok());
  dfu.reset();
  auto again = still_in_bootloader(world);
  ASSERT_TRUE(again);
  // A good image still goes in and starts.
  ASSERT_TRUE(Flasher::flash(*again, make_image(4096), {}, {}).ok());
  world.advance(5000);
  EXPECT_EQ(world.emu().mode(), emu::BoardMode::kApplication);
}

}  // namespace
}  // namespace cathbox::testing
