/* USB device layer: descriptors, standard requests (enumeration), the HID class requests
 * (GET_REPORT / SET_REPORT of feature reports on endpoint 0, idle, protocol) and the glue to
 * the firmware core: interrupt OUT reports are commands, one state report goes IN per frame. */
#include "usb_device.h"

#include <string.h>

#include "board.h"
#include "firmware/cbx_core.h"
#include "protocol/cbx_hid_descriptor.h"
#include "usb_otgfs.h"

enum {
  REQ_GET_STATUS = 0, REQ_CLEAR_FEATURE = 1, REQ_SET_FEATURE = 3, REQ_SET_ADDRESS = 5,
  REQ_GET_DESCRIPTOR = 6, REQ_GET_CONFIGURATION = 8, REQ_SET_CONFIGURATION = 9,
  REQ_GET_INTERFACE = 10, REQ_SET_INTERFACE = 11
};
enum { HID_GET_REPORT = 1, HID_GET_IDLE = 2, HID_GET_PROTOCOL = 3, HID_SET_REPORT = 9,
       HID_SET_IDLE = 10, HID_SET_PROTOCOL = 11 };
enum { DESC_DEVICE = 1, DESC_CONFIGURATION = 2, DESC_STRING = 3, DESC_HID = 0x21, DESC_REPORT = 0x22 };
enum { REPORT_TYPE_INPUT = 1, REPORT_TYPE_OUTPUT = 2, REPORT_TYPE_FEATURE = 3 };
#define TYPE_MASK 0x60u
#define TYPE_STANDARD 0x00u
#define TYPE_CLASS 0x20u
#define RECIPIENT_MASK 0x1Fu
#define RECIPIENT_DEVICE 0u
#define RECIPIENT_INTERFACE 1u
#define RECIPIENT_ENDPOINT 2u
#define FEATURE_ENDPOINT_HALT 0u

static cbx_core* core;
static uint8_t configuration;
static uint8_t idle_rate;
static uint8_t protocol_mode = 1u; /* report protocol */
static usb_setup pending_set_report;
static uint8_t in_report[CBX_REPORT_SIZE];

#define LO(x) (uint8_t)((x) & 0xFFu)
#define HI(x) (uint8_t)(((x) >> 8) & 0xFFu)

static const uint8_t device_descriptor[18] = {
    18, DESC_DEVICE, 0x00, 0x02, /* USB 2.0 */
    0x00, 0x00, 0x00,            /* class per interface */
    USB_EP0_SIZE, LO(CBX_USB_VID), HI(CBX_USB_VID), LO(CBX_USB_PID), HI(CBX_USB_PID),
    LO((CBX_FW_MAJOR << 8) | CBX_FW_MINOR), HI((CBX_FW_MAJOR << 8) | CBX_FW_MINOR),
    1, 2, 3, /* manufacturer, product, serial strings */
    1};

#define CONFIG_LENGTH (9u + 9u + 9u + 7u + 7u)

static uint16_t configuration_descriptor(uint8_t out[CONFIG_LENGTH]) {
  const uint16_t report_length = (uint16_t)cbx_hid_report_descriptor_size;
  const uint8_t d[CONFIG_LENGTH] = {
      9, DESC_CONFIGURATION, LO(CONFIG_LENGTH), HI(CONFIG_LENGTH), 1, 1, 0, 0x80, 50, /* 100 mA */
      9, 4, 0, 0, 2, 0x03, 0x00, 0x00, 0,               /* interface 0: HID, no boot protocol */
      9, DESC_HID, 0x11, 0x01, 0, 1, DESC_REPORT, LO(report_length), HI(report_length),
      7, 5, 0x81, 0x03, LO(USB_EP1_SIZE), HI(USB_EP1_SIZE), 1, /* interrupt IN, 1 ms */
      7, 5, 0x01, 0x03, LO(USB_EP1_SIZE), HI(USB_EP1_SIZE), 1, /* interrupt OUT, 1 ms */
  };
  memcpy(out, d, sizeof d);
  return CONFIG_LENGTH;
}

static uint16_t string_descriptor(uint8_t index, uint8_t out[USB_EP0_BUFFER]) {
  if (index == 0u) {
    out[0] = 4;
    out[1] = DESC_STRING;
    out[2] = 0x09; /* English (US) */
    out[3] = 0x04;
    return 4u;
  }
  const char* text = index == 1u ? "Cathbox" : index == 2u ? "Cathbox haptic box" : NULL;
  if (index == 3u) text = core->config.serial;
  if (!text) return 0u;
  uint16_t n = 0;
  while (text[n] && 2u + 2u * (n + 1u) <= USB_EP0_BUFFER) {
    out[2u + 2u * n] = (uint8_t)text[n];
    out[3u + 2u * n] = 0u;
    n++;
  }
  out[0] = (uint8_t)(2u + 2u * n);
  out[1] = DESC_STRING;
  return (uint16_t)(2u + 2u * n);
}

void usb_device_bind(cbx_core* c) { core = c; }

void usb_device_start(cbx_core* c) {
  usb_device_bind(c);
  usb_otgfs_init();
}

/* The host is gone (bus reset, suspend): the core stops rendering, and the outputs go off
 * now, not after the command watchdog's 50 ms. The core first, so that a control tick
 * preempting this interrupt renders zero too. */
static void host_gone(void) {
  if (core) cbx_core_usb_reset(core);
  board_outputs_off();
}

void usb_device_reset(void) {
  configuration = 0u;
  idle_rate = 0u;
  protocol_mode = 1u;
  host_gone();
}

void usb_device_suspend(void) { host_gone(); }

static bool get_descriptor(const usb_setup* s) {
  uint8_t buffer[USB_EP0_BUFFER];
  uint16_t length = 0;
  const uint8_t type = HI(s->wValue);
  const uint8_t recipient = s->bmRequestType & RECIPIENT_MASK;
  if (recipient == RECIPIENT_DEVICE && type == DESC_DEVICE) {
    usb_ep0_send(device_descriptor, sizeof device_descriptor, s->wLength);
    return true;
  }
  if (recipient == RECIPIENT_DEVICE && type == DESC_CONFIGURATION) {
    length = configuration_descriptor(buffer);
  } else if (recipient == RECIPIENT_DEVICE && type == DESC_STRING) {
    length = string_descriptor(LO(s->wValue), buffer);
  } else if (recipient == RECIPIENT_INTERFACE && type == DESC_REPORT && s->wIndex == 0u) {
    usb_ep0_send(cbx_hid_report_descriptor, (uint16_t)cbx_hid_report_descriptor_size, s->wLength);
    return true;
  } else if (recipient == RECIPIENT_INTERFACE && type == DESC_HID && s->wIndex == 0u) {
    configuration_descriptor(buffer);
    memmove(buffer, buffer + 18, 9);
    length = 9u;
  }
  if (length == 0u) return false; /* includes the device qualifier: full-speed only */
  usb_ep0_send(buffer, length, s->wLength);
  return true;
}

/* The endpoint named by wIndex: 0 always, 1 (IN or OUT) once configured; -1 for any other. */
static int endpoint_number(uint16_t wIndex) {
  const uint16_t number = wIndex & 0x7Fu;
  if ((wIndex & ~0x8Fu) != 0u) return -1;
  if (number == 0u) return 0;
  return number == 1u && configuration == 1u ? 1 : -1;
}

/* USB 2.0 9.4.1/9.4.5/9.4.9: only endpoints have a feature here (HALT); the device does not
 * offer remote wake-up, interfaces have none. The recipient must exist. */
static bool feature_request(const usb_setup* s, uint8_t recipient) {
  if (recipient != RECIPIENT_ENDPOINT || s->wValue != FEATURE_ENDPOINT_HALT) return false;
  const int ep = endpoint_number(s->wIndex);
  if (ep < 0) return false;
  if (ep == 1) usb_ep1_stall((s->wIndex & 0x80u) != 0u, s->bRequest == REQ_SET_FEATURE);
  usb_ep0_status();
  return true;
}

static bool get_status(const usb_setup* s, uint8_t recipient) {
  uint8_t reply[2] = {0u, 0u}; /* device: bus powered, no remote wake-up; interface: 0 */
  if (recipient == RECIPIENT_INTERFACE && s->wIndex != 0u) return false;
  if (recipient == RECIPIENT_ENDPOINT) {
    const int ep = endpoint_number(s->wIndex);
    if (ep < 0) return false;
    if (ep == 1) reply[0] = usb_ep1_stalled((s->wIndex & 0x80u) != 0u) ? 1u : 0u;
  } else if (recipient != RECIPIENT_DEVICE && recipient != RECIPIENT_INTERFACE) {
    return false;
  }
  usb_ep0_send(reply, 2u, s->wLength);
  return true;
}

static bool standard_request(const usb_setup* s) {
  const uint8_t recipient = s->bmRequestType & RECIPIENT_MASK;
  uint8_t reply[2] = {0u, 0u};
  switch (s->bRequest) {
    case REQ_GET_DESCRIPTOR:
      return get_descriptor(s);
    case REQ_SET_ADDRESS:
      if (s->wValue > 127u) return false;
      usb_set_address((uint8_t)s->wValue);
      usb_ep0_status();
      return true;
    case REQ_GET_CONFIGURATION:
      usb_ep0_send(&configuration, 1u, s->wLength);
      return true;
    case REQ_SET_CONFIGURATION:
      if (s->wValue > 1u) return false;
      configuration = (uint8_t)s->wValue;
      usb_ep1_configure(configuration == 1u);
      usb_ep0_status();
      return true;
    case REQ_GET_STATUS:
      return get_status(s, recipient);
    case REQ_CLEAR_FEATURE:
    case REQ_SET_FEATURE:
      return feature_request(s, recipient);
    case REQ_GET_INTERFACE:
      if (configuration != 1u || s->wIndex != 0u) return false;
      usb_ep0_send(reply, 1u, s->wLength);
      return true;
    case REQ_SET_INTERFACE:
      if (configuration != 1u || s->wIndex != 0u || s->wValue != 0u) return false;
      usb_ep0_status();
      return true;
    default:
      return false;
  }
}

/* The report type the descriptor declares for `id`: the state is the input report, the
 * command the output report, every other ID a feature report. */
static uint8_t report_type(uint8_t id) {
  if (id == CBX_ID_STATE) return REPORT_TYPE_INPUT;
  if (id == CBX_ID_COMMAND) return REPORT_TYPE_OUTPUT;
  return REPORT_TYPE_FEATURE;
}

static bool hid_request(const usb_setup* s) {
  uint8_t report[CBX_REPORT_SIZE];
  switch (s->bRequest) {
    case HID_GET_REPORT: {
      const uint8_t type = HI(s->wValue);
      if (type == REPORT_TYPE_OUTPUT || type != report_type(LO(s->wValue))) return false;
      if (cbx_core_usb_feature_get(core, LO(s->wValue), report) != CBX_OK) return false;
      usb_ep0_send(report, CBX_REPORT_SIZE, s->wLength);
      return true;
    }
    case HID_SET_REPORT: {
      const uint8_t type = HI(s->wValue);
      if (type == REPORT_TYPE_INPUT || type != report_type(LO(s->wValue)) || s->wLength == 0u ||
          s->wLength > USB_EP0_BUFFER)
        return false;
      pending_set_report = *s;
      usb_ep0_receive(s->wLength);
      return true;
    }
    case HID_SET_IDLE:
      idle_rate = HI(s->wValue);
      usb_ep0_status();
      return true;
    case HID_GET_IDLE:
      usb_ep0_send(&idle_rate, 1u, s->wLength);
      return true;
    case HID_SET_PROTOCOL:
      protocol_mode = LO(s->wValue);
      usb_ep0_status();
      return true;
    case HID_GET_PROTOCOL:
      usb_ep0_send(&protocol_mode, 1u, s->wLength);
      return true;
    default:
      return false;
  }
}

bool usb_device_setup(const usb_setup* s) {
  const uint8_t type = s->bmRequestType & TYPE_MASK;
  if (type == TYPE_STANDARD) return standard_request(s);
  if (type == TYPE_CLASS && (s->bmRequestType & RECIPIENT_MASK) == RECIPIENT_INTERFACE && s->wIndex == 0u)
    return hid_request(s);
  return false;
}

bool usb_device_ep0_out(const uint8_t* data, uint16_t length) {
  if (pending_set_report.bRequest != HID_SET_REPORT) return false;
  pending_set_report.bRequest = 0u;
  /* A command goes to the core whatever it holds: a bad one latches BAD_COMMAND there. */
  if (HI(pending_set_report.wValue) == REPORT_TYPE_OUTPUT)
    return cbx_core_usb_out_report(core, data, length) == CBX_OK;
  if (length == 0u || data[0] != LO(pending_set_report.wValue)) return false; /* not the named report */
  return cbx_core_usb_feature_set(core, data, length) == CBX_OK;
}

void usb_device_ep1_out(const uint8_t* data, uint16_t length) {
  (void)cbx_core_usb_out_report(core, data, length);
}

/* One state report per frame. The core marks one report due per millisecond of its own clock;
 * when the frame and that millisecond are out of phase (no new one since the last frame), the
 * current state is sent anyway, so the host never misses a frame. A report the endpoint's TX
 * FIFO has no room for is counted (state report in_dropped), not queued: the next frame's
 * report carries the newest state, the seq echo of the last command included. */
void usb_device_sof(void) {
  if (configuration != 1u || usb_ep1_in_busy() || usb_ep1_stalled(true)) return;
  if (!cbx_core_usb_in_report(core, in_report) &&
      cbx_core_usb_feature_get(core, CBX_ID_STATE, in_report) != CBX_OK)
    return;
  if (!usb_ep1_in_send(in_report, CBX_REPORT_SIZE)) cbx_core_usb_in_dropped(core);
}
