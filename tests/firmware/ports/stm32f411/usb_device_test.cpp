// USB device layer of the STM32F411 port against a fake OTG FS driver: what the host sees
// during enumeration and report exchange.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

extern "C" {
#include "fake_hal.h"
#include "protocol/cbx_hid_descriptor.h"
#include "usb_device.h"
#include "usb_otgfs.h"
}

namespace {

struct FakeDriver {
  std::vector<uint8_t> ep0_in;
  int ep0_sends = 0;
  int statuses = 0;
  int stalls = 0;
  uint16_t receive_length = 0;
  int address = -1;
  bool ep1_enabled = false;
  bool ep1_busy = false;
  std::vector<uint8_t> ep1_in;
  bool halted[2] = {false, false};
  int outputs_off = 0;
};
FakeDriver driver;

}  // namespace

extern "C" {
void usb_otgfs_init(void) {}
void usb_otgfs_detach(void) {}
void usb_ep0_send(const uint8_t* data, uint16_t length, uint16_t requested) {
  driver.ep0_in.assign(data, data + (length < requested ? length : requested));
  driver.ep0_sends++;
}
void usb_ep0_receive(uint16_t length) { driver.receive_length = length; }
void usb_ep0_status(void) { driver.statuses++; }
void usb_ep0_stall(void) { driver.stalls++; }
void usb_set_address(uint8_t address) { driver.address = address; }
void usb_ep1_configure(bool enable) { driver.ep1_enabled = enable; }
bool usb_ep1_in_busy(void) { return driver.ep1_busy; }
bool usb_ep1_in_send(const uint8_t* data, uint16_t length) {
  driver.ep1_in.assign(data, data + length);
  driver.ep1_busy = true;
  return true;
}
void usb_ep1_stall(bool in, bool stall) { driver.halted[in ? 1 : 0] = stall; }
void board_outputs_off(void) { driver.outputs_off++; }
bool usb_ep1_stalled(bool in) { return driver.halted[in ? 1 : 0]; }
}

namespace {

class UsbDevice : public testing::Test {
 protected:
  void SetUp() override {
    driver = FakeDriver{};
    cbx_fake_reset();
    const cbx_core_config config = cbx_fake_config(CBX_ENCODER_COUNTER, CBX_ACTUATOR_BRAKE);
    cbx_core_init(&core_, &config);
    usb_device_start(&core_);
    usb_device_reset();
  }

  // One control request's SETUP stage (the name is not Setup: that would hide gtest's
  // misspelling trap testing::Test::Setup, clang's -Woverloaded-virtual).
  bool Control(uint8_t type, uint8_t request, uint16_t value, uint16_t index, uint16_t length) {
    const usb_setup s{type, request, value, index, length};
    return usb_device_setup(&s);
  }

  // One millisecond of core ticks, then a USB frame: the state report it queued, decoded.
  ::testing::AssertionResult Frame(cbx_state_report* state) {
    driver.ep1_in.clear();
    cbx_fake_run_us(&core_, 1000u);
    usb_device_sof();
    if (driver.ep1_in.size() != 64u) return ::testing::AssertionFailure() << "no report queued";
    if (cbx_state_decode(driver.ep1_in.data(), 64, state) != CBX_OK)
      return ::testing::AssertionFailure() << "report does not decode";
    return ::testing::AssertionSuccess();
  }

  cbx_core core_{};
};

TEST_F(UsbDevice, DeviceDescriptorNamesTheBox) {
  ASSERT_TRUE(Control(0x80, 6, 0x0100, 0, 64));
  ASSERT_EQ(driver.ep0_in.size(), 18u);
  EXPECT_EQ(driver.ep0_in[1], 1);
  EXPECT_EQ(driver.ep0_in[7], 64);  // EP0 max packet
  EXPECT_EQ(driver.ep0_in[8] | driver.ep0_in[9] << 8, CBX_USB_VID);
  EXPECT_EQ(driver.ep0_in[10] | driver.ep0_in[11] << 8, CBX_USB_PID);
  // The host first asks for 8 bytes: it gets 8.
  ASSERT_TRUE(Control(0x80, 6, 0x0100, 0, 8));
  EXPECT_EQ(driver.ep0_in.size(), 8u);
}

TEST_F(UsbDevice, ConfigurationIsOneHidInterfaceWithInterruptEndpointsAt1ms) {
  ASSERT_TRUE(Control(0x80, 6, 0x0200, 0, 9));
  ASSERT_EQ(driver.ep0_in.size(), 9u);
  const unsigned total = driver.ep0_in[2] | driver.ep0_in[3] << 8;
  ASSERT_TRUE(Control(0x80, 6, 0x0200, 0, 255));
  const std::vector<uint8_t> d = driver.ep0_in;
  ASSERT_EQ(d.size(), total);
  // Walk the descriptors: every length is consistent and the pieces are there.
  int interfaces = 0, hid = 0, endpoints = 0;
  for (size_t i = 0; i < d.size(); i += d[i]) {
    ASSERT_GE(d[i], 2u);
    ASSERT_LE(i + d[i], d.size());
    if (d[i + 1] == 4) {
      interfaces++;
      EXPECT_EQ(d[i + 5], 3);  // HID
      EXPECT_EQ(d[i + 4], 2);  // two endpoints
    } else if (d[i + 1] == 0x21) {
      hid++;
      EXPECT_EQ(d[i + 6], 0x22);
      EXPECT_EQ(static_cast<size_t>(d[i + 7] | d[i + 8] << 8), cbx_hid_report_descriptor_size);
    } else if (d[i + 1] == 5) {
      endpoints++;
      EXPECT_TRUE(d[i + 2] == 0x81 || d[i + 2] == 0x01);
      EXPECT_EQ(d[i + 3], 3);  // interrupt
      EXPECT_EQ(d[i + 4] | d[i + 5] << 8, 64);
      EXPECT_EQ(d[i + 6], 1);  // bInterval 1 ms
    }
  }
  EXPECT_EQ(interfaces, 1);
  EXPECT_EQ(hid, 1);
  EXPECT_EQ(endpoints, 2);
}

TEST_F(UsbDevice, ReportDescriptorIsTheProtocolOne) {
  ASSERT_TRUE(Control(0x81, 6, 0x2200, 0, 255));
  ASSERT_EQ(driver.ep0_in.size(), cbx_hid_report_descriptor_size);
  EXPECT_EQ(0, std::memcmp(driver.ep0_in.data(), cbx_hid_report_descriptor, cbx_hid_report_descriptor_size));
  ASSERT_TRUE(Control(0x81, 6, 0x2100, 0, 255));  // the HID descriptor alone
  ASSERT_EQ(driver.ep0_in.size(), 9u);
  EXPECT_EQ(driver.ep0_in[1], 0x21);
}

TEST_F(UsbDevice, StringsAndUnknownDescriptors) {
  ASSERT_TRUE(Control(0x80, 6, 0x0300, 0, 255));
  EXPECT_EQ(driver.ep0_in, (std::vector<uint8_t>{4, 3, 0x09, 0x04}));
  ASSERT_TRUE(Control(0x80, 6, 0x0303, 0x0409, 255));
  ASSERT_EQ(driver.ep0_in.size(), 2u + 2u * 8u);  // "CBX-0001"
  EXPECT_EQ(driver.ep0_in[2], 'C');
  EXPECT_EQ(driver.ep0_in[3], 0);
  EXPECT_FALSE(Control(0x80, 6, 0x0600, 0, 10));  // device qualifier: full speed only, stall
  EXPECT_FALSE(Control(0x80, 6, 0x0309, 0, 255));
  EXPECT_FALSE(Control(0x40, 1, 0, 0, 0));        // vendor request
}

TEST_F(UsbDevice, AddressConfigurationAndHalt) {
  ASSERT_TRUE(Control(0x00, 5, 7, 0, 0));
  EXPECT_EQ(driver.address, 7);
  EXPECT_EQ(driver.statuses, 1);
  ASSERT_TRUE(Control(0x00, 9, 1, 0, 0));
  EXPECT_TRUE(driver.ep1_enabled);
  ASSERT_TRUE(Control(0x80, 8, 0, 0, 1));
  EXPECT_EQ(driver.ep0_in, (std::vector<uint8_t>{1}));
  EXPECT_FALSE(Control(0x00, 9, 2, 0, 0));
  ASSERT_TRUE(Control(0x02, 3, 0, 0x81, 0));  // SET_FEATURE(ENDPOINT_HALT) on 0x81
  ASSERT_TRUE(Control(0x82, 0, 0, 0x81, 2));
  EXPECT_EQ(driver.ep0_in, (std::vector<uint8_t>{1, 0}));
  ASSERT_TRUE(Control(0x02, 1, 0, 0x81, 0));  // CLEAR_FEATURE
  EXPECT_FALSE(driver.halted[1]);
  ASSERT_TRUE(Control(0x00, 9, 0, 0, 0));
  EXPECT_FALSE(driver.ep1_enabled);
}

TEST_F(UsbDevice, StateGoesInOncePerFrameAndCommandsComeOut) {
  ASSERT_TRUE(Control(0x00, 9, 1, 0, 0));
  cbx_state_report state;
  ASSERT_TRUE(Frame(&state));
  EXPECT_EQ(state.header.seq, 1);
  EXPECT_EQ(state.header.time_us, 1000u);
  // A frame with no new millisecond of the core's clock still gets the current state.
  driver.ep1_busy = false;
  usb_device_sof();
  ASSERT_EQ(cbx_state_decode(driver.ep1_in.data(), 64, &state), CBX_OK);
  EXPECT_EQ(state.header.seq, 2);
  // Busy endpoint: nothing new is queued until the host took the last one.
  cbx_fake_run_us(&core_, 1000u);
  driver.ep1_in.clear();
  usb_device_sof();
  EXPECT_TRUE(driver.ep1_in.empty());
  driver.ep1_busy = false;
  usb_device_sof();
  EXPECT_EQ(driver.ep1_in.size(), 64u);

  const cbx_vector* command = cbx_fake_vector("command_brake_law");
  ASSERT_NE(command, nullptr);
  usb_device_ep1_out(command->bytes, 64);
  cbx_fake_tick(&core_);
  EXPECT_EQ(cbx_fake_state(&core_).command_seq_echo, 0x1234);
}

TEST_F(UsbDevice, FeatureReportsOnEndpointZero) {
  ASSERT_TRUE(Control(0xA1, 1, 0x0310, 0, 64));  // GET_REPORT feature 0x10
  ASSERT_EQ(driver.ep0_in.size(), 64u);
  cbx_device_info info;
  ASSERT_EQ(cbx_device_info_decode(driver.ep0_in.data(), 64, &info), CBX_OK);
  EXPECT_STREQ(info.board, "fake");
  EXPECT_FALSE(Control(0xA1, 1, 0x0314, 0, 64));  // bootloader report cannot be read: stall

  const cbx_vector* calibration = cbx_fake_vector("calibration_identity");
  ASSERT_NE(calibration, nullptr);
  ASSERT_TRUE(Control(0x21, 9, 0x0311, 0, 64));  // SET_REPORT feature 0x11: data stage follows
  EXPECT_EQ(driver.receive_length, 64u);
  EXPECT_TRUE(usb_device_ep0_out(calibration->bytes, 64));
  cbx_fake_tick(&core_);
  EXPECT_TRUE(cbx_fake_state(&core_).status & CBX_STATUS_CALIBRATED);

  const cbx_vector* bad = cbx_fake_vector("bad_curve_order");
  ASSERT_NE(bad, nullptr);
  ASSERT_TRUE(Control(0x21, 9, 0x0311, 0, 64));
  EXPECT_FALSE(usb_device_ep0_out(bad->bytes, 64));  // rejected: the driver stalls
  EXPECT_FALSE(usb_device_ep0_out(calibration->bytes, 64));  // no SET_REPORT pending

  ASSERT_TRUE(Control(0x21, 10, 0, 0, 0));  // SET_IDLE
  ASSERT_TRUE(Control(0xA1, 3, 0, 0, 1));   // GET_PROTOCOL: report protocol
  EXPECT_EQ(driver.ep0_in, (std::vector<uint8_t>{1}));
  EXPECT_FALSE(Control(0x21, 9, 0x0311, 0, 200));  // longer than any report
  EXPECT_FALSE(Control(0xA1, 1, 0x0210, 0, 64));   // GET_REPORT of an output report
}

TEST_F(UsbDevice, BootloaderRequestThroughSetReport) {
  const cbx_vector* v = cbx_fake_vector("enter_bootloader");
  ASSERT_NE(v, nullptr);
  ASSERT_TRUE(Control(0x21, 9, 0x0314, 0, 64));
  EXPECT_TRUE(usb_device_ep0_out(v->bytes, 64));
  EXPECT_EQ(cbx_fake.bootloader_requests, 1u);
}

// USB 2.0 9.4: requests naming an endpoint, interface or feature that does not exist, or an
// endpoint other than 0 before the device is configured, are request errors (stall).
TEST_F(UsbDevice, RequestErrorsStall) {
  EXPECT_FALSE(Control(0x00, 5, 128, 0, 0));     // SET_ADDRESS beyond 127
  EXPECT_FALSE(Control(0x82, 0, 0, 0x81, 2));    // GET_STATUS of EP1 while not configured
  EXPECT_FALSE(Control(0x02, 3, 0, 0x81, 0));    // SET_FEATURE(HALT) on EP1 while not configured
  EXPECT_FALSE(driver.halted[1]);
  ASSERT_TRUE(Control(0x82, 0, 0, 0x80, 2));     // EP0 always exists
  ASSERT_TRUE(Control(0x00, 9, 1, 0, 0));
  EXPECT_FALSE(Control(0x82, 0, 0, 0x82, 2));    // GET_STATUS of an endpoint the device lacks
  EXPECT_FALSE(Control(0x82, 0, 0, 0x02, 2));
  EXPECT_FALSE(Control(0x81, 0, 0, 1, 2));       // GET_STATUS of interface 1
  EXPECT_FALSE(Control(0x02, 3, 5, 0x81, 0));    // an endpoint feature other than HALT
  EXPECT_FALSE(Control(0x00, 3, 1, 0, 0));       // DEVICE_REMOTE_WAKEUP: not offered (bmAttributes)
  EXPECT_FALSE(Control(0x01, 3, 0, 0, 0));       // interfaces have no features
  EXPECT_FALSE(Control(0x81, 10, 0, 1, 1));      // GET_INTERFACE of interface 1
  EXPECT_FALSE(driver.halted[0]);
  EXPECT_FALSE(driver.halted[1]);
  ASSERT_TRUE(Control(0x02, 3, 0, 0x01, 0));     // HALT on EP1 OUT once configured
  EXPECT_TRUE(driver.halted[0]);
  ASSERT_TRUE(Control(0x82, 0, 0, 0x01, 2));
  EXPECT_EQ(driver.ep0_in, (std::vector<uint8_t>{1, 0}));
}

// HID 1.11 7.2.1/7.2.2: wValue names the report type and ID; a report of another type or ID
// than the one named is a request error, and SET_REPORT's data must be the named report.
TEST_F(UsbDevice, ReportTypeAndIdMustMatch) {
  EXPECT_FALSE(Control(0xA1, 1, 0x0110, 0, 64));  // device info is a feature, not an input report
  EXPECT_FALSE(Control(0xA1, 1, 0x0301, 0, 64));  // the state is an input, not a feature report
  ASSERT_TRUE(Control(0xA1, 1, 0x0101, 0, 64));   // GET_REPORT(Input, state)
  cbx_state_report state;
  EXPECT_EQ(cbx_state_decode(driver.ep0_in.data(), 64, &state), CBX_OK);

  const cbx_vector* bootloader = cbx_fake_vector("enter_bootloader");
  ASSERT_NE(bootloader, nullptr);
  ASSERT_TRUE(Control(0x21, 9, 0x0311, 0, 64));   // announced as calibration...
  EXPECT_FALSE(usb_device_ep0_out(bootloader->bytes, 64));  // ...but the data is 0x14
  EXPECT_EQ(cbx_fake.bootloader_requests, 0u);
  const cbx_vector* command = cbx_fake_vector("command_brake_law");
  ASSERT_NE(command, nullptr);
  ASSERT_TRUE(Control(0x21, 9, 0x0202, 0, 64));   // SET_REPORT(Output, command) on EP0
  EXPECT_TRUE(usb_device_ep0_out(command->bytes, 64));
  cbx_fake_tick(&core_);
  EXPECT_EQ(cbx_fake_state(&core_).command_seq_echo, 0x1234);
  EXPECT_FALSE(Control(0x21, 9, 0x0302, 0, 64));  // the command is not a feature report
  // A bad command on EP0 is a bad command like one on EP1: counted, BAD_COMMAND latched.
  ASSERT_TRUE(Control(0x21, 9, 0x0202, 0, 64));
  EXPECT_FALSE(usb_device_ep0_out(bootloader->bytes, 64));
  cbx_fake_tick(&core_);
  EXPECT_TRUE(cbx_fake_state(&core_).faults & CBX_FAULT_BAD_COMMAND);
  EXPECT_EQ(cbx_fake_state(&core_).rx_errors, 1);
  EXPECT_EQ(cbx_fake.bootloader_requests, 0u);
}

// A halted interrupt IN endpoint takes no reports (they would go out stale once the host
// clears the halt); after CLEAR_FEATURE(HALT) the next frame carries the current state.
TEST_F(UsbDevice, HaltedInEndpointQueuesNothing) {
  ASSERT_TRUE(Control(0x00, 9, 1, 0, 0));
  ASSERT_TRUE(Control(0x02, 3, 0, 0x81, 0));
  cbx_state_report state;
  EXPECT_FALSE(Frame(&state));
  ASSERT_TRUE(Control(0x02, 1, 0, 0x81, 0));
  ASSERT_TRUE(Frame(&state));
  EXPECT_EQ(state.header.time_us, 2000u);
}

}  // namespace
