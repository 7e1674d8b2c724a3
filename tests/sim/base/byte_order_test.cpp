// base::put_le / get_le write and read the same bytes as the protocol's C helpers (cbx_bytes.h),
// which the firmware and the golden vectors use.
#include "base/byte_order.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>

#include "protocol/cbx_bytes.h"

namespace cathbox::base {
namespace {

TEST(ByteOrder, LeastSignificantByteFirst) {
  std::array<std::uint8_t, 8> b{};
  put_le<std::uint32_t>(b.data(), 0x11223344u);
  EXPECT_EQ(b[0], 0x44);
  EXPECT_EQ(b[1], 0x33);
  EXPECT_EQ(b[2], 0x22);
  EXPECT_EQ(b[3], 0x11);
  EXPECT_EQ(b[4], 0x00);  // nothing past the field
}

TEST(ByteOrder, SameBytesAsTheProtocolHelpers) {
  const std::uint64_t values[] = {0, 1, 0xFF, 0x8000, 0xFFFF, 0x12345678, 0x80000000u, 0xFFFFFFFFu,
                                  0x0123456789ABCDEFull, 0xFFFFFFFFFFFFFFFFull};
  for (const std::uint64_t v : values) {
    std::array<std::uint8_t, 8> ours{}, theirs{};
    put_le(ours.data(), static_cast<std::uint16_t>(v));
    cbx_put_u16(theirs.data(), static_cast<std::uint16_t>(v));
    EXPECT_EQ(ours, theirs) << v;
    EXPECT_EQ(get_le<std::uint16_t>(theirs.data()), cbx_get_u16(theirs.data()));
    put_le(ours.data(), static_cast<std::uint32_t>(v));
    cbx_put_u32(theirs.data(), static_cast<std::uint32_t>(v));
    EXPECT_EQ(ours, theirs) << v;
    EXPECT_EQ(get_le<std::uint32_t>(theirs.data()), cbx_get_u32(theirs.data()));
    put_le(ours.data(), v);
    cbx_put_u64(theirs.data(), v);
    EXPECT_EQ(ours, theirs) << v;
    EXPECT_EQ(get_le<std::uint64_t>(theirs.data()), v);
  }
}

}  // namespace
}  // namespace cathbox::base
