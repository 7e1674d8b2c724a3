#include <gtest/gtest.h>

#include <cstring>

#include "protocol/cbx_crc16.h"

TEST(Crc16, CheckValueOfCcittFalse) {
  const char* text = "123456789";
  EXPECT_EQ(cbx_crc16(reinterpret_cast<const uint8_t*>(text), std::strlen(text)), 0x29B1u);
}

TEST(Crc16, EmptyInputIsInitialValue) { EXPECT_EQ(cbx_crc16(nullptr, 0), 0xFFFFu); }

TEST(Crc16, UpdateContinuesAcrossChunks) {
  const uint8_t data[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  for (size_t split = 0; split <= sizeof data; ++split) {
    const uint16_t first = cbx_crc16(data, split);
    EXPECT_EQ(cbx_crc16_update(first, data + split, sizeof data - split), cbx_crc16(data, sizeof data))
        << "split at " << split;
  }
}

// The table-driven implementation against the bitwise definition (MSB first, polynomial
// 0x1021): every byte value from many register states, so every table entry is exercised.
TEST(Crc16, TableMatchesTheBitwiseDefinition) {
  const auto bitwise = [](uint16_t crc, uint8_t byte) {
    crc = static_cast<uint16_t>(crc ^ (byte << 8));
    for (int bit = 0; bit < 8; ++bit)
      crc = static_cast<uint16_t>((crc & 0x8000u) ? (crc << 1) ^ 0x1021u : crc << 1);
    return crc;
  };
  for (uint32_t start = 0; start <= 0xFFFFu; start += 257u) {
    for (uint32_t b = 0; b < 256u; ++b) {
      const uint8_t byte = static_cast<uint8_t>(b);
      ASSERT_EQ(cbx_crc16_update(static_cast<uint16_t>(start), &byte, 1), bitwise(static_cast<uint16_t>(start), byte))
          << "state " << start << " byte " << b;
    }
  }
}
