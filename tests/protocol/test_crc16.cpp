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
