// Walks the HID report descriptor with the short-item grammar (HID 1.11, 6.2.2) and the
// checks the Linux kernel's parser applies (hid-core.c), then checks that the declared report
// sizes equal what the encoders produce.
#include <gtest/gtest.h>

#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "protocol/cbx_hid_descriptor.h"
#include "protocol/cbx_protocol.h"

namespace {

enum class MainKind { kInput, kOutput, kFeature };

struct Walk {
  std::map<std::pair<MainKind, unsigned>, unsigned> bits;  // (kind, report id) -> bits
  unsigned usage_page = 0;
  int max_depth = 0;
  bool ids_used = false;
  bool ids_missing = false;
};

Walk walk(const uint8_t* d, size_t n) {
  Walk w;
  unsigned report_size = 0, report_count = 0, report_id = 0;
  long logical_min = 0, logical_max = 0;
  bool have_usage = false;
  int depth = 0;
  size_t i = 0;
  while (i < n) {
    const uint8_t prefix = d[i++];
    if (prefix == 0xFE) throw std::runtime_error("long item");
    const unsigned size = (prefix & 3u) == 3u ? 4u : (prefix & 3u);
    const unsigned type = (prefix >> 2) & 3u;
    const unsigned tag = prefix >> 4;
    if (i + size > n) throw std::runtime_error("item runs past the end");
    unsigned long value = 0;
    for (unsigned b = 0; b < size; ++b) value |= static_cast<unsigned long>(d[i + b]) << (8 * b);
    long signed_value = static_cast<long>(value);
    if (size > 0 && size < 4 && (value >> (8 * size - 1)) & 1u) signed_value -= 1L << (8 * size);
    i += size;
    if (type == 0) {  // main
      if (tag == 0xA) {
        if (!have_usage) throw std::runtime_error("collection without usage");
        ++depth;
        w.max_depth = std::max(w.max_depth, depth);
      } else if (tag == 0xC) {
        if (depth == 0) throw std::runtime_error("end collection without collection");
        --depth;
      } else if (tag == 0x8 || tag == 0x9 || tag == 0xB) {
        if (depth == 0) throw std::runtime_error("main item outside a collection");
        if (report_size == 0 || report_size > 256) throw std::runtime_error("bad report size");
        if (report_count == 0 || report_count > 12288) throw std::runtime_error("bad report count");
        if (logical_max < logical_min) throw std::runtime_error("logical max < min");
        if (report_id == 0) w.ids_missing = true; else w.ids_used = true;
        const MainKind kind = tag == 0x8 ? MainKind::kInput : tag == 0x9 ? MainKind::kOutput : MainKind::kFeature;
        w.bits[{kind, report_id}] += report_size * report_count;
      } else {
        throw std::runtime_error("unknown main tag");
      }
      have_usage = false;
    } else if (type == 1) {  // global
      switch (tag) {
        case 0: w.usage_page = static_cast<unsigned>(value); break;
        case 1: logical_min = signed_value; break;
        case 2: logical_max = size == 2 && value <= 0xFFFF ? static_cast<long>(value) : signed_value; break;
        case 7: report_size = static_cast<unsigned>(value); break;
        case 8:
          if (value == 0 || value > 255) throw std::runtime_error("report id out of range");
          report_id = static_cast<unsigned>(value);
          break;
        case 9: report_count = static_cast<unsigned>(value); break;
        default: break;
      }
    } else if (type == 2) {  // local
      if (tag == 0) have_usage = true;
    } else {
      throw std::runtime_error("reserved item type");
    }
  }
  if (depth != 0) throw std::runtime_error("unbalanced collections");
  return w;
}

}  // namespace

TEST(HidDescriptor, ParsesUnderTheShortItemGrammar) {
  Walk w;
  ASSERT_NO_THROW(w = walk(cbx_hid_report_descriptor, cbx_hid_report_descriptor_size));
  EXPECT_GE(w.usage_page, 0xFF00u) << "vendor-defined usage page";
  EXPECT_EQ(w.max_depth, 1);
  EXPECT_EQ(cbx_hid_report_descriptor_size, 65u) << "protocol/README.md lists 65 bytes";
  EXPECT_TRUE(w.ids_used);
  EXPECT_FALSE(w.ids_missing) << "report IDs are all or nothing";
}

TEST(HidDescriptor, DeclaredSizesEqualTheEncodersLengths) {
  const Walk w = walk(cbx_hid_report_descriptor, cbx_hid_report_descriptor_size);
  const unsigned payload_bits = (CBX_REPORT_SIZE - 1) * 8;  // the report ID byte is not counted
  const std::map<std::pair<MainKind, unsigned>, unsigned> expected = {
      {{MainKind::kInput, CBX_ID_STATE}, payload_bits},
      {{MainKind::kOutput, CBX_ID_COMMAND}, payload_bits},
      {{MainKind::kFeature, CBX_ID_DEVICE_INFO}, payload_bits},
      {{MainKind::kFeature, CBX_ID_CALIBRATION}, payload_bits},
      {{MainKind::kFeature, CBX_ID_LIMITS}, payload_bits},
      {{MainKind::kFeature, CBX_ID_RESET_COUNTERS}, payload_bits},
      {{MainKind::kFeature, CBX_ID_ENTER_BOOTLOADER}, payload_bits},
      {{MainKind::kFeature, CBX_ID_SELFTEST}, payload_bits},
  };
  EXPECT_EQ(w.bits, expected);
  // One full-speed interrupt packet per report: ID + payload = 64 bytes.
  EXPECT_EQ(payload_bits / 8 + 1, 64u);
}

TEST(HidDescriptor, WalkerRejectsBrokenDescriptors) {
  const uint8_t truncated[] = {0x06, 0x00};
  EXPECT_THROW(walk(truncated, sizeof truncated), std::runtime_error);
  const uint8_t unbalanced[] = {0x06, 0x00, 0xFF, 0x09, 0x01, 0xA1, 0x01};
  EXPECT_THROW(walk(unbalanced, sizeof unbalanced), std::runtime_error);
  const uint8_t zero_id[] = {0x06, 0x00, 0xFF, 0x09, 0x01, 0xA1, 0x01, 0x85, 0x00, 0xC0};
  EXPECT_THROW(walk(zero_id, sizeof zero_id), std::runtime_error);
}
