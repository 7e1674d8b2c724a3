// The firmware image info block: every golden vector decodes to its values (field by field)
// and encodes to its bytes; bad ones are refused with their status, leaving the output alone;
// short input, NULL, and what the emulator and host rely on (the block is found at its offset).
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <string>

#include "cbx_vectors.h"

namespace {

const cbx_image_info_vector* find(const std::string& name) {
  for (size_t i = 0; i < cbx_image_info_vector_count; ++i)
    if (name == cbx_image_info_vectors[i].name) return &cbx_image_info_vectors[i];
  return nullptr;
}

TEST(ImageInfo, GoodVectorsDecodeToTheirValuesAndEncodeToTheirBytes) {
  int good = 0;
  for (size_t i = 0; i < cbx_image_info_vector_count; ++i) {
    const auto& v = cbx_image_info_vectors[i];
    if (v.expect != CBX_OK) continue;
    ++good;
    cbx_image_info d;
    std::memset(&d, 0xA5, sizeof d);
    ASSERT_EQ(cbx_image_info_decode(v.bytes, sizeof v.bytes, &d), CBX_OK) << v.name;
    EXPECT_EQ(d.fw_major, v.value.fw_major) << v.name;
    EXPECT_EQ(d.fw_minor, v.value.fw_minor) << v.name;
    EXPECT_EQ(d.fw_patch, v.value.fw_patch) << v.name;
    EXPECT_EQ(d.protocol_minor, v.value.protocol_minor) << v.name;
    EXPECT_STREQ(d.board, v.value.board) << v.name;
    EXPECT_STREQ(d.build, v.value.build) << v.name;
    EXPECT_EQ(d.image_size, v.value.image_size) << v.name;
    std::array<uint8_t, CBX_IMAGE_INFO_SIZE> out{};
    ASSERT_EQ(cbx_image_info_encode(&v.value, out.data()), CBX_OK) << v.name;
    EXPECT_EQ(std::memcmp(out.data(), v.bytes, out.size()), 0) << v.name;
  }
  EXPECT_GE(good, 1);
}

TEST(ImageInfo, BadVectorsAreRefusedWithoutTouchingTheOutput) {
  int bad = 0;
  for (size_t i = 0; i < cbx_image_info_vector_count; ++i) {
    const auto& v = cbx_image_info_vectors[i];
    if (v.expect == CBX_OK) continue;
    ++bad;
    cbx_image_info d;
    std::memset(&d, 0x5A, sizeof d);
    EXPECT_EQ(cbx_image_info_decode(v.bytes, sizeof v.bytes, &d), v.expect) << v.name;
    const auto* raw = reinterpret_cast<const unsigned char*>(&d);
    for (size_t k = 0; k < sizeof d; ++k) ASSERT_EQ(raw[k], 0x5A) << v.name << " wrote its output";
  }
  EXPECT_GE(bad, 4);
}

TEST(ImageInfo, ShortInputNullAndTextAfterPaddingAreRefused) {
  const auto* good = find("image_info_1_1_0");
  ASSERT_NE(good, nullptr);
  cbx_image_info d;
  EXPECT_EQ(cbx_image_info_decode(good->bytes, CBX_IMAGE_INFO_SIZE - 1, &d), CBX_ERR_LENGTH);
  EXPECT_EQ(cbx_image_info_decode(nullptr, CBX_IMAGE_INFO_SIZE, &d), CBX_ERR_NULL);
  EXPECT_EQ(cbx_image_info_decode(good->bytes, CBX_IMAGE_INFO_SIZE, nullptr), CBX_ERR_NULL);
  std::array<uint8_t, CBX_IMAGE_INFO_SIZE> stray{};
  std::memcpy(stray.data(), good->bytes, stray.size());
  stray[34] = 0;  // the build identifier ends one byte early ...
  stray[35] = 'x';  // ... and text follows its padding
  EXPECT_EQ(cbx_image_info_decode(stray.data(), stray.size(), &d), CBX_ERR_RANGE);
  stray = {};
  std::memcpy(stray.data(), good->bytes, stray.size());
  stray[12] = 0x7F;  // a control character in the board name
  EXPECT_EQ(cbx_image_info_decode(stray.data(), stray.size(), &d), CBX_ERR_RANGE);
  cbx_image_info too_big = good->value;
  too_big.image_size = CBX_IMAGE_MAX_SIZE + 1u;
  EXPECT_EQ(cbx_image_info_encode(&too_big, stray.data()), CBX_ERR_RANGE);
}

}  // namespace
