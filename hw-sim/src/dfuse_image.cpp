#include "emu/dfuse_image.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <utility>

#include "emu/stm32_machine.hpp"

namespace cathbox::emu {
namespace {

constexpr size_t kPrefixBytes = 11;         // "DfuSe", bVersion, DFUImageSize, bTargets
constexpr size_t kTargetPrefixBytes = 274;  // "Target", bAlternateSetting, bTargetNamed, name[255], size, count
constexpr size_t kElementHeaderBytes = 8;   // dwElementAddress, dwElementSize
constexpr size_t kSuffixBytes = 16;         // bcdDevice, idProduct, idVendor, bcdDFU, "UFD", bLength, dwCRC
constexpr uint32_t kFlashBase = 0x08000000u;
constexpr uint32_t kMaxElements = 256;      // far more than an image has; bounds the overlap check

uint32_t le32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 | static_cast<uint32_t>(p[2]) << 16 |
         static_cast<uint32_t>(p[3]) << 24;
}
uint16_t le16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | p[1] << 8); }

// DFU 1.1's suffix CRC: reflected 0x04C11DB7, initial 0xFFFFFFFF, no final XOR.
uint32_t dfu_crc(std::span<const uint8_t> bytes) {
  uint32_t crc = 0xFFFFFFFFu;
  for (const uint8_t b : bytes) {
    crc ^= b;
    for (int bit = 0; bit < 8; ++bit) crc = (crc & 1u) != 0 ? (crc >> 1) ^ 0xEDB88320u : crc >> 1;
  }
  return crc;
}

std::string hex32(uint32_t v) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%08x", v);
  return text;
}

class Reader {
 public:
  Reader(std::span<const uint8_t> file, std::string name) : file_(file), name_(std::move(name)) {}

  Result<DfuseFlashImage> read() {
    if (file_.size() < kPrefixBytes + kSuffixBytes) {
      return fail(0, "file of " + std::to_string(file_.size()) + " bytes is shorter than a DfuSe prefix and suffix (27)");
    }
    body_ = file_.size() - kSuffixBytes;
    if (auto suffix = read_suffix(); !suffix) return suffix.error();
    const uint8_t* p = file_.data();
    if (std::memcmp(p, "DfuSe", 5) != 0) return fail(0, "no 'DfuSe' signature: not a DfuSe file");
    if (p[5] != 1) return fail(5, "DfuSe version " + std::to_string(p[5]) + " (only 1 exists)");
    if (le32(p + 6) != body_) {
      return fail(6, "DFUImageSize " + std::to_string(le32(p + 6)) + " but the file holds " + std::to_string(body_) +
                         " bytes before its suffix");
    }
    const uint8_t targets = p[10];
    if (targets == 0) return fail(10, "no targets");
    size_t at = kPrefixBytes;
    for (uint8_t t = 0; t < targets; ++t) {
      if (auto target = read_target(t, at); !target) return target.error();
    }
    if (at != body_) return fail(at, std::to_string(body_ - at) + " bytes after the last target");
    if (image_.flash.empty()) return fail(kPrefixBytes, "no bytes for the flash (every element is empty)");
    return std::move(image_);
  }

 private:
  Error fail(size_t offset, const std::string& what) const {
    return Error{name_ + ": byte " + std::to_string(offset) + ": " + what};
  }

  Status read_suffix() {
    const uint8_t* s = file_.data() + body_;
    if (std::memcmp(s + 8, "UFD", 3) != 0) return fail(body_ + 8, "no DFU suffix signature 'UFD': truncated or not a .dfu file");
    if (s[11] != kSuffixBytes) return fail(body_ + 11, "DFU suffix length " + std::to_string(s[11]) + " (DfuSe: 16)");
    if (le16(s + 6) != 0x011A) return fail(body_ + 6, "bcdDFU " + hex32(le16(s + 6)) + " is not DfuSe's 0x011a");
    const uint32_t stored = le32(s + 12);
    const uint32_t computed = dfu_crc(file_.first(file_.size() - 4));
    if (stored != computed) {
      return fail(body_ + 12, "suffix CRC " + hex32(stored) + " does not match the content's " + hex32(computed) + ": corrupt file");
    }
    image_.bcd_device = le16(s);
    return base::Ok{};
  }

  Status read_target(uint8_t index, size_t& at) {
    const std::string which = "target " + std::to_string(index);
    if (kTargetPrefixBytes > body_ - at) return fail(at, which + ": prefix runs past the suffix");
    const uint8_t* t = file_.data() + at;
    if (std::memcmp(t, "Target", 6) != 0) return fail(at, which + ": no 'Target' signature");
    if (t[6] != 0) {
      return fail(at + 6, which + ": alternate setting " + std::to_string(t[6]) +
                              "; only 0 (internal flash) is emulated (option bytes, OTP are not)");
    }
    const uint32_t size = le32(t + 266);
    const uint32_t count = le32(t + 270);
    at += kTargetPrefixBytes;
    if (size > body_ - at) return fail(at - 8, which + ": dwTargetSize " + std::to_string(size) + " runs past the suffix");
    const size_t end = at + size;
    if (count > kMaxElements) return fail(at - 4, which + ": " + std::to_string(count) + " elements (at most 256)");
    for (uint32_t e = 0; e < count; ++e) {
      const std::string element = which + " element " + std::to_string(e);
      if (kElementHeaderBytes > end - at) return fail(at, element + ": header runs past the target's size");
      const uint32_t address = le32(file_.data() + at);
      const uint32_t bytes = le32(file_.data() + at + 4);
      at += kElementHeaderBytes;
      if (bytes > end - at) return fail(at - 4, element + ": " + std::to_string(bytes) + " bytes run past the target's size");
      if (address < kFlashBase || address - kFlashBase > Stm32Machine::kFlashSize ||
          bytes > Stm32Machine::kFlashSize - (address - kFlashBase)) {
        return fail(at - 8, element + ": " + hex32(address) + " + " + std::to_string(bytes) +
                                " bytes lies outside the flash (0x08000000, 512 KiB)");
      }
      if (auto placed = place(address - kFlashBase, file_.subspan(at, bytes), at - 8, element); !placed) return placed.error();
      at += bytes;
    }
    if (at != end) return fail(at, which + ": " + std::to_string(end - at) + " bytes after its last element");
    image_.elements += count;
    return base::Ok{};
  }

  Status place(uint32_t offset, std::span<const uint8_t> data, size_t header_at, const std::string& element) {
    if (data.empty()) return base::Ok{};
    for (const auto& [from, to] : placed_) {
      if (offset < to && from < offset + data.size()) {
        return fail(header_at, element + ": " + hex32(kFlashBase + offset) + " overlaps an earlier element at " + hex32(kFlashBase + from));
      }
    }
    placed_.emplace_back(offset, offset + static_cast<uint32_t>(data.size()));
    if (image_.flash.size() < offset + data.size()) image_.flash.resize(offset + data.size(), 0xFF);
    std::copy(data.begin(), data.end(), image_.flash.begin() + offset);
    return base::Ok{};
  }

  std::span<const uint8_t> file_;
  std::string name_;
  size_t body_ = 0;
  DfuseFlashImage image_;
  std::vector<std::pair<uint32_t, uint32_t>> placed_;
};

}  // namespace

Result<DfuseFlashImage> read_dfuse(std::span<const uint8_t> file, const std::string& name) { return Reader(file, name).read(); }

bool is_dfuse_name(const std::string& name) {
  if (name.size() < 4) return false;
  std::string tail = name.substr(name.size() - 4);
  std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return tail == ".dfu";
}

}  // namespace cathbox::emu
