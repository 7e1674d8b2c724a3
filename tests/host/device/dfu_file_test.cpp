// DfuSe files: round trip, the suffix CRC, and one clear refusal per malformed field.
#include <gtest/gtest.h>

#include "device/dfu_file.hpp"
#include "device/dfuse_layout.hpp"
#include "protocol/cbx_bytes.h"

namespace cathbox::device {
namespace {

DfuImage sample() {
  DfuImage image;
  image.bcd_device = 0x0102;
  image.vid = 0x0483;
  image.pid = 0xDF11;
  image.target_name = "cathbox stm32f411";
  image.elements.push_back({0x08000000u, {1, 2, 3, 4, 5, 6, 7, 8}});
  image.elements.push_back({0x08004000u, std::vector<uint8_t>(300, 0xAB)});
  return image;
}

TEST(DfuFile, Crc32OfCheckStringWithoutFinalXor) {
  const std::string check = "123456789";
  EXPECT_EQ(DfuFile::crc32({reinterpret_cast<const uint8_t*>(check.data()), check.size()}), ~0xCBF43926u);
}

TEST(DfuFile, RoundTrip) {
  const auto bytes = DfuFile::write(sample());
  EXPECT_EQ(bytes.size(), 11u + 274u + 8u + 8u + 8u + 300u + 16u);
  EXPECT_EQ(std::string(bytes.end() - 8, bytes.end() - 5), "UFD");
  auto back = DfuFile::parse(bytes, "x.dfu");
  ASSERT_TRUE(back.ok()) << back.error().message;
  const auto& image = back.value();
  EXPECT_EQ(image.bcd_device, 0x0102);
  EXPECT_EQ(image.vid, 0x0483);
  EXPECT_EQ(image.pid, 0xDF11);
  EXPECT_EQ(image.target_name, "cathbox stm32f411");
  ASSERT_EQ(image.elements.size(), 2u);
  EXPECT_EQ(image.elements[1].address, 0x08004000u);
  EXPECT_EQ(image.elements[1].data, std::vector<uint8_t>(300, 0xAB));
  EXPECT_EQ(image.total_bytes(), 308u);
}

TEST(DfuFile, EveryByteFlipIsCaughtByTheSuffixCrc) {
  const auto bytes = DfuFile::write(sample());
  for (size_t i = 0; i + 4 < bytes.size(); i += 7) {
    auto bad = bytes;
    bad[i] ^= 0x01;
    auto parsed = DfuFile::parse(bad, "x.dfu");
    ASSERT_FALSE(parsed.ok()) << "byte " << i;
    EXPECT_EQ(parsed.error().code, Errc::kBadImage);
  }
}

// Rewrites the suffix CRC so that a structural error behind it is reached.
std::vector<uint8_t> with_crc(std::vector<uint8_t> bytes) {
  const uint32_t crc = DfuFile::crc32({bytes.data(), bytes.size() - 4});
  cbx_put_u32(bytes.data() + bytes.size() - 4, crc);
  return bytes;
}

TEST(DfuFile, StructuralErrorsNameTheField) {
  const auto good = DfuFile::write(sample());
  struct Case {
    size_t offset;
    uint8_t value;
    const char* expect;
  };
  const Case cases[] = {
      {0, 'X', "prefix"},          {6, 0x00, "DFUImageSize"}, {10, 2, "targets"},
      {11, 'X', "Target"},          {11 + 266, 0x00, "dwTargetSize"}, {11 + 270, 0, "elements"},
      {11 + 274 + 4, 0xFF, "size"},
  };
  for (const auto& c : cases) {
    auto bad = good;
    bad[c.offset] = c.value;
    auto parsed = DfuFile::parse(with_crc(bad), "x.dfu");
    ASSERT_FALSE(parsed.ok()) << c.expect;
    EXPECT_NE(parsed.error().message.find(c.expect), std::string::npos) << parsed.error().message;
    EXPECT_NE(parsed.error().message.find("x.dfu: byte "), std::string::npos);
  }
  EXPECT_FALSE(DfuFile::parse(std::vector<uint8_t>(10, 0), "short.dfu").ok());
  const std::vector<uint8_t> cut(good.begin(), good.end() - 20);
  EXPECT_FALSE(DfuFile::parse(cut, "cut.dfu").ok());
}

TEST(DfuseLayout, ParsesTheStm32f411RomString) {
  auto layout = DfuseLayout::parse("@Internal Flash  /0x08000000/04*016Kg,01*064Kg,03*128Kg");
  ASSERT_TRUE(layout.ok()) << layout.error().message;
  const auto& l = layout.value();
  EXPECT_EQ(l.name(), "Internal Flash");
  ASSERT_EQ(l.sectors().size(), 8u);
  EXPECT_EQ(l.sectors()[4].address, 0x08010000u);
  EXPECT_EQ(l.sectors()[4].size, 64u * 1024u);
  EXPECT_EQ(l.sectors()[7].address, 0x08060000u);
  ASSERT_NE(l.find(0x08005000u), nullptr);
  EXPECT_EQ(l.find(0x08005000u)->address, 0x08004000u);
  EXPECT_EQ(l.find(0x08080000u), nullptr);
  EXPECT_TRUE(l.covers(0x08000000u, 512u * 1024u));
  EXPECT_FALSE(l.covers(0x0807FFFFu, 2));
}

TEST(DfuseLayout, ReadOnlyRegionsAreNotCovered) {
  auto layout = DfuseLayout::parse("@Option Bytes  /0x1FFFC000/01*016 e");
  ASSERT_TRUE(layout.ok()) << layout.error().message;
  EXPECT_FALSE(layout.value().sectors()[0].erasable);
  EXPECT_FALSE(layout.value().covers(0x1FFFC000u, 4));
}

TEST(DfuseLayout, RefusesMalformedStrings) {
  for (const char* bad : {"", "Internal", "@Flash", "@Flash /0x08000000", "@Flash /0x08000000/04016Kg",
                          "@Flash /0x08000000/04*016Kz", "@Flash /0x08000000/00*016Kg", "@Flash /0xFFFFFFFF/02*016Kg",
                          // sizes whose K/M multiple wraps 64 bits (to 1 MiB, to 0) or overflows strtoull
                          "@Flash /0x08000000/01*18014398509481985Mg", "@Flash /0x08000000/01*18014398509481984Mg",
                          "@Flash /0x08000000/01*99999999999999999999Kg"}) {
    auto layout = DfuseLayout::parse(bad);
    EXPECT_FALSE(layout.ok()) << bad;
  }
}

}  // namespace
}  // namespace cathbox::device
