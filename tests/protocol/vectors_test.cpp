// Every golden vector: good ones decode and re-encode byte for byte, bad ones are rejected
// with their documented status and leave the output untouched.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <set>

#include "vector_helpers.hpp"

using cathbox::protocol::test::vectors_where;

namespace {
using Bytes = std::array<uint8_t, CBX_REPORT_SIZE>;
union AnyReport {
  decltype(cbx_vector::value) value;
  unsigned char raw[sizeof(decltype(cbx_vector::value))];
};
}  // namespace

TEST(GoldenVectors, CoverEveryReportKind) {
  std::set<std::string> kinds;
  for (const auto* v : vectors_where(true)) kinds.insert(v->kind);
  EXPECT_EQ(kinds, (std::set<std::string>{"state", "command", "device_info", "calibration", "limits",
                                          "reset_counters", "enter_bootloader", "selftest"}));
  std::set<cbx_status> errors;
  for (const auto* v : vectors_where(false)) errors.insert(v->expect);
  EXPECT_EQ(errors, (std::set<cbx_status>{CBX_ERR_LENGTH, CBX_ERR_REPORT_ID, CBX_ERR_VERSION,
                                          CBX_ERR_CRC, CBX_ERR_RANGE}));
}

TEST(GoldenVectors, GoodVectorsEncodeToTheirBytes) {
  for (const auto* v : vectors_where(true)) {
    Bytes out{};
    ASSERT_EQ(cbx_vector_encode(v, out.data()), CBX_OK) << v->name;
    EXPECT_EQ(std::memcmp(out.data(), v->bytes, CBX_REPORT_SIZE), 0) << v->name;
  }
}

TEST(GoldenVectors, GoodVectorsDecodeAndReencodeByteForByte) {
  for (const auto* v : vectors_where(true)) {
    cbx_vector decoded = *v;
    std::memset(&decoded.value, 0xA5, sizeof decoded.value);
    ASSERT_EQ(cbx_vector_decode(v, &decoded.value), CBX_OK) << v->name;
    // Encoding covers every field, so equal bytes mean equal decoded values.
    Bytes out{};
    ASSERT_EQ(cbx_vector_encode(&decoded, out.data()), CBX_OK) << v->name;
    EXPECT_EQ(std::memcmp(out.data(), v->bytes, CBX_REPORT_SIZE), 0) << v->name;
  }
}

TEST(GoldenVectors, BadVectorsAreRejectedWithoutTouchingTheOutput) {
  for (const auto* v : vectors_where(false)) {
    AnyReport out;
    std::memset(out.raw, 0x5A, sizeof out.raw);
    EXPECT_EQ(cbx_vector_decode(v, &out.value), v->expect) << v->name;
    for (unsigned char byte : out.raw) ASSERT_EQ(byte, 0x5A) << v->name << " wrote its output";
  }
}

TEST(GoldenVectors, EverySingleBitFlipIsRejected) {
  for (const auto* v : vectors_where(true)) {
    for (size_t bit = 0; bit < CBX_REPORT_SIZE * 8; ++bit) {
      cbx_vector flipped = *v;
      flipped.bytes[bit / 8] = static_cast<uint8_t>(flipped.bytes[bit / 8] ^ (1u << (bit % 8)));
      AnyReport out;
      const cbx_status status = cbx_vector_decode(&flipped, &out.value);
      const cbx_status expected = bit < 8 ? CBX_ERR_REPORT_ID : bit < 16 ? CBX_ERR_VERSION : CBX_ERR_CRC;
      ASSERT_EQ(status, expected) << v->name << " bit " << bit;
    }
  }
}
