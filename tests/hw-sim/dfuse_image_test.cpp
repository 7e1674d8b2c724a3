// The DfuSe reader of `cathbox-emu --image FILE.dfu`: a file laid out as ST's UM0391 describes
// (and `cathbox flash pack` writes) becomes the flash bytes; every malformed field is refused
// with one line naming the byte offset.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "emu/dfuse_image.hpp"
#include "protocol/cbx_bytes.h"

namespace cathbox::emu {
namespace {

struct Element {
  uint32_t address;
  std::vector<uint8_t> data;
};

void put32(std::vector<uint8_t>& out, uint32_t v) {
  out.resize(out.size() + 4);
  cbx_put_u32(out.data() + out.size() - 4, v);
}
void put16(std::vector<uint8_t>& out, uint16_t v) {
  out.resize(out.size() + 2);
  cbx_put_u16(out.data() + out.size() - 2, v);
}

// CRC-32 as DFU 1.1's suffix has it, written here independently (table-free, MSB test per bit).
uint32_t reference_crc(const std::vector<uint8_t>& bytes) {
  uint32_t crc = 0xFFFFFFFFu;
  for (const uint8_t b : bytes) {
    for (int bit = 0; bit < 8; ++bit) {
      const bool mix = ((crc ^ (b >> bit)) & 1u) != 0;
      crc >>= 1;
      if (mix) crc ^= 0xEDB88320u;
    }
  }
  return crc;
}

// A DfuSe file: one target per entry of `targets`, alternate setting `alt`.
std::vector<uint8_t> dfuse(const std::vector<std::vector<Element>>& targets, uint8_t alt = 0) {
  std::vector<uint8_t> out = {'D', 'f', 'u', 'S', 'e', 1, 0, 0, 0, 0, static_cast<uint8_t>(targets.size())};
  for (const auto& elements : targets) {
    for (const char c : std::string("Target")) out.push_back(static_cast<uint8_t>(c));
    out.push_back(alt);
    put32(out, 1);
    const std::string name = "cathbox stm32f411";
    out.insert(out.end(), name.begin(), name.end());
    out.resize(out.size() + 255 - name.size(), 0);
    uint32_t size = 0;
    for (const auto& e : elements) size += 8 + static_cast<uint32_t>(e.data.size());
    put32(out, size);
    put32(out, static_cast<uint32_t>(elements.size()));
    for (const auto& e : elements) {
      put32(out, e.address);
      put32(out, static_cast<uint32_t>(e.data.size()));
      out.insert(out.end(), e.data.begin(), e.data.end());
    }
  }
  cbx_put_u32(out.data() + 6, static_cast<uint32_t>(out.size()));
  put16(out, 0x0100);  // bcdDevice 1.0
  put16(out, 0xDF11);
  put16(out, 0x0483);
  put16(out, 0x011A);
  out.push_back('U');
  out.push_back('F');
  out.push_back('D');
  out.push_back(16);
  put32(out, reference_crc(out));
  return out;
}

// Re-signs a file after a test edited its body, so the field under test is what fails.
void resign(std::vector<uint8_t>& file) {
  file.resize(file.size() - 4);
  put32(file, reference_crc(file));
}

std::string error_of(const std::vector<uint8_t>& file) {
  auto read = read_dfuse(file, "fw.dfu");
  return read ? std::string("(read)") : read.error().message;
}

const std::vector<uint8_t> kVectors = {0x00, 0x00, 0x02, 0x20, 0x01, 0x02, 0x00, 0x08};

TEST(DfuseImage, OneElementBecomesTheFlashFromItsBase) {
  const auto read = read_dfuse(dfuse({{{0x08000000u, kVectors}}}), "fw.dfu");
  ASSERT_TRUE(read) << read.error().message;
  EXPECT_EQ(read.value().flash, kVectors);
  EXPECT_EQ(read.value().bcd_device, 0x0100);
  EXPECT_EQ(read.value().elements, 1u);
}

TEST(DfuseImage, ElementsAcrossTargetsPlacedWithErasedGaps) {
  const auto read = read_dfuse(dfuse({{{0x08000000u, kVectors}}, {{0x08004000u, {0xAA, 0xBB}}, {0x08000010u, {0x11}}}}), "fw.dfu");
  ASSERT_TRUE(read) << read.error().message;
  const auto& flash = read.value().flash;
  ASSERT_EQ(flash.size(), 0x4002u);
  EXPECT_EQ(flash[7], 0x08);
  EXPECT_EQ(flash[8], 0xFF);
  EXPECT_EQ(flash[0x10], 0x11);
  EXPECT_EQ(flash[0x3FFF], 0xFF);
  EXPECT_EQ(flash[0x4000], 0xAA);
  EXPECT_EQ(flash[0x4001], 0xBB);
  EXPECT_EQ(read.value().elements, 3u);
}

TEST(DfuseImage, SuffixFieldsCheckedAtTheirOffsets) {
  const auto good = dfuse({{{0x08000000u, kVectors}}});
  const size_t suffix = good.size() - 16;
  auto crc = good;
  crc[300] ^= 0x01;  // a bit of the element's data
  EXPECT_EQ(error_of(crc).rfind("fw.dfu: byte " + std::to_string(suffix + 12) + ": suffix CRC 0x", 0), 0u) << error_of(crc);
  EXPECT_NE(error_of(crc).find("corrupt file"), std::string::npos);
  auto ufd = good;
  ufd[suffix + 9] = 'X';
  EXPECT_EQ(error_of(ufd), "fw.dfu: byte " + std::to_string(suffix + 8) + ": no DFU suffix signature 'UFD': truncated or not a .dfu file");
  auto length = good;
  length[suffix + 11] = 12;
  EXPECT_EQ(error_of(length), "fw.dfu: byte " + std::to_string(suffix + 11) + ": DFU suffix length 12 (DfuSe: 16)");
  auto bcd_dfu = good;
  bcd_dfu[suffix + 6] = 0x10;
  bcd_dfu[suffix + 7] = 0x01;
  resign(bcd_dfu);
  EXPECT_EQ(error_of(bcd_dfu), "fw.dfu: byte " + std::to_string(suffix + 6) + ": bcdDFU 0x00000110 is not DfuSe's 0x011a");
  EXPECT_EQ(error_of(std::vector<uint8_t>(good.begin(), good.begin() + 20)),
            "fw.dfu: byte 0: file of 20 bytes is shorter than a DfuSe prefix and suffix (27)");
  auto truncated = good;
  truncated.resize(good.size() - 3);
  EXPECT_NE(error_of(truncated).find("no DFU suffix signature"), std::string::npos);
}

TEST(DfuseImage, PrefixAndTargetFieldsCheckedAtTheirOffsets) {
  const auto good = dfuse({{{0x08000000u, kVectors}}});
  auto edit = [&](size_t at, uint8_t value) {
    auto file = good;
    file[at] = value;
    resign(file);
    return error_of(file);
  };
  EXPECT_EQ(edit(0, 'd'), "fw.dfu: byte 0: no 'DfuSe' signature: not a DfuSe file");
  EXPECT_EQ(edit(5, 2), "fw.dfu: byte 5: DfuSe version 2 (only 1 exists)");
  EXPECT_EQ(edit(6, 0), "fw.dfu: byte 6: DFUImageSize " + std::to_string(good[7] << 8) + " but the file holds " +
                            std::to_string(good.size() - 16) + " bytes before its suffix");
  EXPECT_EQ(edit(10, 0), "fw.dfu: byte 10: no targets");
  EXPECT_EQ(edit(10, 2), "fw.dfu: byte " + std::to_string(good.size() - 16) + ": target 1: prefix runs past the suffix");
  EXPECT_EQ(edit(11, 't'), "fw.dfu: byte 11: target 0: no 'Target' signature");
  EXPECT_EQ(edit(17, 1), "fw.dfu: byte 17: target 0: alternate setting 1; only 0 (internal flash) is emulated (option bytes, OTP are not)");
  EXPECT_EQ(edit(11 + 266, 0xFF), "fw.dfu: byte 277: target 0: dwTargetSize 255 runs past the suffix");
  EXPECT_EQ(edit(11 + 266, 15), "fw.dfu: byte 289: target 0 element 0: 8 bytes run past the target's size");
  EXPECT_EQ(edit(11 + 266, 17), "fw.dfu: byte 277: target 0: dwTargetSize 17 runs past the suffix");
  EXPECT_EQ(edit(11 + 270, 2), "fw.dfu: byte 301: target 0 element 1: header runs past the target's size");
  EXPECT_EQ(edit(11 + 270, 0), "fw.dfu: byte 285: target 0: 16 bytes after its last element");
  EXPECT_EQ(edit(11 + 271, 1), "fw.dfu: byte 281: target 0: 257 elements (at most 256)");
}

TEST(DfuseImage, ElementsOutsideTheFlashOrOverlappingRefused) {
  EXPECT_EQ(error_of(dfuse({{{0x20000000u, kVectors}}})),
            "fw.dfu: byte 285: target 0 element 0: 0x20000000 + 8 bytes lies outside the flash (0x08000000, 512 KiB)");
  EXPECT_EQ(error_of(dfuse({{{0x0807FFFCu, kVectors}}})),
            "fw.dfu: byte 285: target 0 element 0: 0x0807fffc + 8 bytes lies outside the flash (0x08000000, 512 KiB)");
  EXPECT_EQ(error_of(dfuse({{{0x08000000u, kVectors}, {0x08000004u, {1, 2}}}})),
            "fw.dfu: byte 301: target 0 element 1: 0x08000004 overlaps an earlier element at 0x08000000");
  EXPECT_EQ(error_of(dfuse({{{0x08000000u, {}}}})), "fw.dfu: byte 11: no bytes for the flash (every element is empty)");
  const auto last_word = read_dfuse(dfuse({{{0x0807FFFCu, {1, 2, 3, 4}}}}), "fw.dfu");
  ASSERT_TRUE(last_word) << last_word.error().message;
  EXPECT_EQ(last_word.value().flash.size(), 512u * 1024u);
}

TEST(DfuseImage, NameDecidesTheFormat) {
  EXPECT_TRUE(is_dfuse_name("build/fw.dfu"));
  EXPECT_TRUE(is_dfuse_name("FW.DFU"));
  EXPECT_FALSE(is_dfuse_name("fw.bin"));
  EXPECT_FALSE(is_dfuse_name("dfu"));
}

}  // namespace
}  // namespace cathbox::emu
