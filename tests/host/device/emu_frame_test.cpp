// The emulator socket framing (protocol/cbx_emu_frame.h): round trips and every rejection.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "protocol/cbx_emu_frame.h"
#include "protocol/cbx_usb_requests.h"

namespace {

std::vector<uint8_t> encode(const cbx_emu_frame& frame) {
  std::vector<uint8_t> out(CBX_EMU_FRAME_MAX);
  const int n = cbx_emu_frame_encode(&frame, out.data(), out.size());
  EXPECT_GT(n, 0);
  out.resize(n > 0 ? static_cast<size_t>(n) : 0u);
  return out;
}

// The HELLO vectors of protocol/README.md ("Emulator socket transport"): the application
// (1209:CB01) and the ROM bootloader (0483:DF11).
TEST(EmuFrame, HelloVectorsEncodeAndDecodeExactly) {
  struct Vector {
    cbx_emu_hello hello;
    std::array<uint8_t, CBX_EMU_HELLO_FRAME> bytes;
  };
  const Vector vectors[] = {{{0x1209, 0xCB01}, {0x01, 0x00, 0x00, 0x00, 0x09, 0x12, 0x01, 0xCB}},
                            {{0x0483, 0xDF11}, {0x01, 0x00, 0x00, 0x00, 0x83, 0x04, 0x11, 0xDF}}};
  for (const Vector& v : vectors) {
    std::array<uint8_t, CBX_EMU_FRAME_MAX> out{};
    ASSERT_EQ(cbx_emu_hello_encode(&v.hello, out.data(), out.size()), static_cast<int>(CBX_EMU_HELLO_FRAME));
    EXPECT_TRUE(std::equal(v.bytes.begin(), v.bytes.end(), out.begin()));
    cbx_emu_frame frame{};
    ASSERT_EQ(cbx_emu_frame_decode(v.bytes.data(), v.bytes.size(), &frame), CBX_OK);
    cbx_emu_hello back{0, 0};
    ASSERT_EQ(cbx_emu_hello_decode(&frame, &back), CBX_OK);
    EXPECT_EQ(back.vid, v.hello.vid);
    EXPECT_EQ(back.pid, v.hello.pid);
  }
}

TEST(EmuFrame, HelloRefusesOtherKindsSizesAndSmallBuffers) {
  const cbx_emu_hello hello{0x1209, 0xCB01};
  std::array<uint8_t, CBX_EMU_HELLO_FRAME - 1> small{};
  EXPECT_EQ(cbx_emu_hello_encode(&hello, small.data(), small.size()), CBX_ERR_LENGTH);
  std::array<uint8_t, CBX_REPORT_SIZE> report{};
  cbx_emu_frame in{};
  in.kind = CBX_EMU_IN;
  in.data = report.data();
  in.data_length = report.size();
  cbx_emu_hello out{7, 7};
  EXPECT_EQ(cbx_emu_hello_decode(&in, &out), CBX_ERR_RANGE);
  cbx_emu_frame short_hello{};
  short_hello.kind = CBX_EMU_HELLO;
  short_hello.data = report.data();
  short_hello.data_length = 2;
  EXPECT_EQ(cbx_emu_hello_decode(&short_hello, &out), CBX_ERR_LENGTH);
  EXPECT_EQ(out.vid, 7);
  EXPECT_EQ(out.pid, 7);
}

TEST(EmuFrame, InterruptReportRoundTrip) {
  std::array<uint8_t, CBX_REPORT_SIZE> report{};
  for (size_t i = 0; i < report.size(); ++i) report[i] = static_cast<uint8_t>(i * 7);
  cbx_emu_frame frame{};
  frame.kind = CBX_EMU_OUT;
  frame.data = report.data();
  frame.data_length = report.size();
  const auto bytes = encode(frame);
  ASSERT_EQ(bytes.size(), 68u);
  EXPECT_EQ(bytes[0], CBX_EMU_OUT);
  cbx_emu_frame back{};
  ASSERT_EQ(cbx_emu_frame_decode(bytes.data(), bytes.size(), &back), CBX_OK);
  EXPECT_EQ(back.kind, CBX_EMU_OUT);
  ASSERT_EQ(back.data_length, 64u);
  EXPECT_TRUE(std::equal(report.begin(), report.end(), back.data));
}

TEST(EmuFrame, ControlRequestCarriesSetupAndOutStage) {
  std::array<uint8_t, 10> data{1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  cbx_emu_frame frame{};
  frame.kind = CBX_EMU_CONTROL;
  frame.tag = 0xBEEF;
  frame.setup = {CBX_DFU_OUT_TYPE, CBX_DFU_DNLOAD, 2, 0, static_cast<uint16_t>(data.size())};
  frame.data = data.data();
  frame.data_length = data.size();
  const auto bytes = encode(frame);
  ASSERT_EQ(bytes.size(), 4u + 8u + 10u);
  EXPECT_EQ(bytes[2], 0xEF);
  EXPECT_EQ(bytes[3], 0xBE);
  cbx_emu_frame back{};
  ASSERT_EQ(cbx_emu_frame_decode(bytes.data(), bytes.size(), &back), CBX_OK);
  EXPECT_EQ(back.tag, 0xBEEF);
  EXPECT_EQ(back.setup.request, CBX_DFU_DNLOAD);
  EXPECT_EQ(back.setup.value, 2);
  EXPECT_EQ(back.setup.length, 10);
  EXPECT_EQ(back.data_length, 10u);
}

TEST(EmuFrame, InRequestHasNoDataStage) {
  cbx_emu_frame frame{};
  frame.kind = CBX_EMU_CONTROL;
  frame.setup = {CBX_USB_HID_GET_TYPE, CBX_USB_HID_GET_REPORT, 0x0310, 0, 64};
  const auto bytes = encode(frame);
  EXPECT_EQ(bytes.size(), 12u);
  cbx_emu_frame back{};
  EXPECT_EQ(cbx_emu_frame_decode(bytes.data(), bytes.size(), &back), CBX_OK);
  EXPECT_EQ(back.data, nullptr);
}

TEST(EmuFrame, RejectsBadFramesWithoutTouchingOutput) {
  cbx_emu_frame untouched{};
  untouched.tag = 77;
  const std::vector<std::vector<uint8_t>> bad_length = {
      {0x02}, {0x02, 0, 0, 0}, std::vector<uint8_t>(67, 0x02), std::vector<uint8_t>(69, 0x02),
      {0x04, 0, 0, 0, 0x21, 1, 0, 0, 0, 0, 4, 0, 1, 2},  // OUT stage 2 bytes, wLength 4
      {0x04, 0, 0, 0, 0xA1, 1, 0, 0, 0, 0, 4, 0, 1},     // IN request with data
      {0x01, 0, 0, 0, 1, 2, 3}};                         // hello of 3 bytes
  for (const auto& bytes : bad_length) {
    std::vector<uint8_t> in = bytes;
    if (in.size() > 4 && (in[0] == 0x02)) in[1] = 0;
    cbx_emu_frame frame = untouched;
    EXPECT_EQ(cbx_emu_frame_decode(in.data(), in.size(), &frame), CBX_ERR_LENGTH) << in.size();
    EXPECT_EQ(frame.tag, 77);
  }
  std::vector<uint8_t> unknown = {0x09, 0, 0, 0};
  cbx_emu_frame frame = untouched;
  EXPECT_EQ(cbx_emu_frame_decode(unknown.data(), unknown.size(), &frame), CBX_ERR_RANGE);
  std::vector<uint8_t> bad_status = {0x05, 7, 0, 0};
  EXPECT_EQ(cbx_emu_frame_decode(bad_status.data(), bad_status.size(), &frame), CBX_ERR_RANGE);
  EXPECT_EQ(frame.tag, 77);
  EXPECT_EQ(cbx_emu_frame_decode(nullptr, 4, &frame), CBX_ERR_NULL);
}

TEST(EmuFrame, EncoderRefusesWrongSizes) {
  std::array<uint8_t, 63> short_report{};
  cbx_emu_frame frame{};
  frame.kind = CBX_EMU_IN;
  frame.data = short_report.data();
  frame.data_length = short_report.size();
  std::array<uint8_t, 128> out{};
  EXPECT_EQ(cbx_emu_frame_encode(&frame, out.data(), out.size()), CBX_ERR_LENGTH);
  std::array<uint8_t, 64> report{};
  frame.data = report.data();
  frame.data_length = report.size();
  EXPECT_EQ(cbx_emu_frame_encode(&frame, out.data(), 40), CBX_ERR_LENGTH);
  frame.kind = 0x33;
  EXPECT_EQ(cbx_emu_frame_encode(&frame, out.data(), out.size()), CBX_ERR_RANGE);
}

TEST(EmuFrame, DefaultSocketPathFollowsEnvironment) {
  char path[108];
  setenv("CATHBOX_EMU_SOCKET", "/x/y.sock", 1);
  ASSERT_EQ(cbx_emu_default_socket_path(path, sizeof path), CBX_OK);
  EXPECT_STREQ(path, "/x/y.sock");
  unsetenv("CATHBOX_EMU_SOCKET");
  setenv("XDG_RUNTIME_DIR", "/run/user/1000", 1);
  ASSERT_EQ(cbx_emu_default_socket_path(path, sizeof path), CBX_OK);
  EXPECT_STREQ(path, "/run/user/1000/cathbox-emu.sock");
  unsetenv("XDG_RUNTIME_DIR");
  ASSERT_EQ(cbx_emu_default_socket_path(path, sizeof path), CBX_OK);
  EXPECT_STREQ(path, "/tmp/cathbox-emu.sock");
  EXPECT_EQ(cbx_emu_default_socket_path(path, 4), CBX_ERR_LENGTH);
}

}  // namespace
