// Decoder and encoder contracts beyond the vectors: lengths, NULLs, check order, ranges.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <set>
#include <stdexcept>
#include <string>

#include "protocol/cbx_crc16.h"
#include "vector_helpers.hpp"

using cathbox::protocol::test::vectors_where;

namespace {
const cbx_vector& vector_named(const std::string& name) {
  for (size_t i = 0; i < cbx_vector_count; ++i) {
    if (name == cbx_vectors[i].name) return cbx_vectors[i];
  }
  throw std::runtime_error("no vector " + name);
}
}  // namespace

TEST(Codecs, EveryDecoderChecksTheLength) {
  for (const auto* v : vectors_where(true)) {
    for (size_t length : {size_t{0}, size_t{1}, size_t{63}, size_t{65}, size_t{128}}) {
      cbx_vector shortened = *v;
      shortened.length = length;
      decltype(cbx_vector::value) out;
      EXPECT_EQ(cbx_vector_decode(&shortened, &out), CBX_ERR_LENGTH) << v->name << " " << length;
    }
  }
}

TEST(Codecs, NullPointersAreErrors) {
  uint8_t buffer[CBX_REPORT_SIZE] = {};
  cbx_state_report state{};
  EXPECT_EQ(cbx_state_decode(nullptr, CBX_REPORT_SIZE, &state), CBX_ERR_NULL);
  EXPECT_EQ(cbx_state_decode(buffer, CBX_REPORT_SIZE, nullptr), CBX_ERR_NULL);
  EXPECT_EQ(cbx_state_encode(nullptr, buffer), CBX_ERR_NULL);
  EXPECT_EQ(cbx_command_encode(nullptr, buffer), CBX_ERR_NULL);
  EXPECT_EQ(cbx_report_peek_id(nullptr, 64), CBX_ERR_NULL);
}

TEST(Codecs, VersionIsCheckedBeforeTheCrc) {
  // A v2 peer may lay out its CRC differently: the host must say "incompatible", not "corrupt".
  cbx_vector v2 = vector_named("state_idle");
  v2.bytes[1] = 2;
  cbx_state_report out{};
  EXPECT_EQ(cbx_vector_decode(&v2, &out), CBX_ERR_VERSION);
}

TEST(Codecs, PeekIdNeedsOnlyTheLength) {
  const cbx_vector& v = vector_named("command_brake_law");
  EXPECT_EQ(cbx_report_peek_id(v.bytes, CBX_REPORT_SIZE), CBX_ID_COMMAND);
  EXPECT_EQ(cbx_report_peek_id(v.bytes, 10), CBX_ERR_LENGTH);
}

TEST(Codecs, EncodersRefuseOutOfRangeValues) {
  uint8_t out[CBX_REPORT_SIZE];
  cbx_command_report command = vector_named("command_brake_law").value.command;
  command.mode = 3;
  EXPECT_EQ(cbx_command_encode(&command, out), CBX_ERR_RANGE);
  command = vector_named("command_brake_law").value.command;
  command.insertion.stiffness = -1;
  EXPECT_EQ(cbx_command_encode(&command, out), CBX_ERR_RANGE);
  command = vector_named("command_brake_law").value.command;
  command.flags = 0x80;
  EXPECT_EQ(cbx_command_encode(&command, out), CBX_ERR_RANGE);

  cbx_state_report state = vector_named("state_pushing").value.state;
  state.faults = 0x8000;
  EXPECT_EQ(cbx_state_encode(&state, out), CBX_ERR_RANGE);

  cbx_limits limits = vector_named("limits_default").value.limits;
  limits.max_force_mN = 50001;
  EXPECT_EQ(cbx_limits_encode(&limits, out), CBX_ERR_RANGE);

  cbx_selftest selftest = vector_named("selftest_start").value.selftest;
  selftest.failed_checks = CBX_CHECK_ESTOP;  // failures only with state FAILED
  EXPECT_EQ(cbx_selftest_encode(&selftest, out), CBX_ERR_RANGE);

  cbx_reset_counters reset = vector_named("reset_counters_all").value.reset_counters;
  reset.mask = 0;
  EXPECT_EQ(cbx_reset_counters_encode(&reset, out), CBX_ERR_RANGE);

  cbx_device_info info = vector_named("device_info").value.device_info;
  info.serial[3] = '\n';
  EXPECT_EQ(cbx_device_info_encode(&info, out), CBX_ERR_RANGE);
}

TEST(Codecs, TextFieldsRoundTripAtFullWidth) {
  cbx_device_info info = vector_named("device_info").value.device_info;
  std::strcpy(info.serial, "0123456789ABCDEF");  // exactly 16 characters, no NUL on the wire
  uint8_t bytes[CBX_REPORT_SIZE];
  ASSERT_EQ(cbx_device_info_encode(&info, bytes), CBX_OK);
  cbx_device_info decoded{};
  ASSERT_EQ(cbx_device_info_decode(bytes, sizeof bytes, &decoded), CBX_OK);
  EXPECT_STREQ(decoded.serial, "0123456789ABCDEF");
  EXPECT_STREQ(decoded.board, "stm32f411-bp");
}

TEST(Codecs, ReservedBytesAreIgnoredOnReceive) {
  // Minor versions may add fields in reserved bytes; a v1.0 decoder ignores them.
  cbx_vector v = vector_named("state_pushing");
  v.bytes[50] = 0x77;
  v.bytes[62] = 0;
  v.bytes[63] = 0;
  const uint16_t crc = cbx_crc16(v.bytes, CBX_CRC_OFFSET);
  v.bytes[62] = static_cast<uint8_t>(crc & 0xFF);
  v.bytes[63] = static_cast<uint8_t>(crc >> 8);
  cbx_state_report out{};
  ASSERT_EQ(cbx_vector_decode(&v, &out), CBX_OK);
  EXPECT_EQ(out.insertion_count, 123456);
}

TEST(Codecs, StatusNamesAreDistinct) {
  std::set<std::string> names;
  for (cbx_status s : {CBX_OK, CBX_ERR_NULL, CBX_ERR_LENGTH, CBX_ERR_REPORT_ID, CBX_ERR_VERSION,
                       CBX_ERR_CRC, CBX_ERR_RANGE, CBX_ERR_STATE}) {
    names.insert(cbx_status_name(s));
  }
  EXPECT_EQ(names.size(), 8u);
}
