#include "device/dfu_file.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

#include "protocol/cbx_bytes.h"

namespace cathbox::device {
namespace {

constexpr size_t kPrefixSize = 11;
constexpr size_t kTargetPrefixSize = 274;
constexpr size_t kTargetNameSize = 255;
constexpr size_t kElementHeaderSize = 8;
constexpr size_t kSuffixSize = 16;

// Grows out by n bytes and returns where they start, for the cbx_put_* writers.
uint8_t* grow(std::vector<uint8_t>& out, size_t n) {
  out.resize(out.size() + n);
  return out.data() + out.size() - n;
}
void put_text(std::vector<uint8_t>& out, const char* text, size_t n) {
  for (size_t i = 0; i < n; ++i) out.push_back(static_cast<uint8_t>(text[i]));
}

Error bad(const std::string& name, size_t offset, const std::string& what) {
  return make_error(Errc::kBadImage, name + ": byte " + std::to_string(offset) + ": " + what);
}

}  // namespace

size_t DfuImage::total_bytes() const {
  size_t n = 0;
  for (const auto& e : elements) n += e.data.size();
  return n;
}

uint32_t DfuFile::crc32(std::span<const uint8_t> bytes) {
  uint32_t crc = 0xFFFFFFFFu;
  for (const uint8_t b : bytes) {
    crc ^= b;
    for (int i = 0; i < 8; ++i) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return crc;
}

Result<DfuImage> DfuFile::parse(std::span<const uint8_t> bytes, const std::string& name) {
  if (bytes.size() < kPrefixSize + kSuffixSize) {
    return bad(name, 0, "file of " + std::to_string(bytes.size()) + " bytes is too short for a DfuSe image");
  }
  const uint8_t* suffix = bytes.data() + bytes.size() - kSuffixSize;
  const size_t suffix_at = bytes.size() - kSuffixSize;
  if (std::memcmp(suffix + 8, "UFD", 3) != 0 || suffix[11] != kSuffixSize) {
    return bad(name, suffix_at + 8, "no DFU suffix (signature 'UFD', length 16): truncated or not a .dfu file");
  }
  const uint32_t stored_crc = cbx_get_u32(suffix + 12);
  const uint32_t crc = crc32(bytes.first(bytes.size() - 4));
  if (stored_crc != crc) {
    char text[96];
    std::snprintf(text, sizeof text, "suffix CRC 0x%08x does not match the content (0x%08x): corrupt file", stored_crc, crc);
    return bad(name, suffix_at + 12, text);
  }
  DfuImage image;
  image.bcd_device = cbx_get_u16(suffix);
  image.pid = cbx_get_u16(suffix + 2);
  image.vid = cbx_get_u16(suffix + 4);
  if (cbx_get_u16(suffix + 6) != 0x011A) return bad(name, suffix_at + 6, "bcdDFU is not 0x011A (DfuSe)");

  const uint8_t* p = bytes.data();
  if (std::memcmp(p, "DfuSe", 5) != 0 || p[5] != 0x01) return bad(name, 0, "prefix is not 'DfuSe' version 1");
  const uint32_t image_size = cbx_get_u32(p + 6);
  if (image_size != suffix_at) {
    return bad(name, 6, "DFUImageSize " + std::to_string(image_size) + " but the body is " + std::to_string(suffix_at) + " bytes");
  }
  const uint8_t targets = p[10];
  if (targets != 1) return bad(name, 10, std::to_string(targets) + " targets; a Cathbox image has exactly 1");
  size_t at = kPrefixSize;
  if (at + kTargetPrefixSize > suffix_at) return bad(name, at, "target prefix runs past the end");
  const uint8_t* t = p + at;
  if (std::memcmp(t, "Target", 6) != 0) return bad(name, at, "target signature is not 'Target'");
  image.alt_setting = t[6];
  const char* raw_name = reinterpret_cast<const char*>(t + 11);
  image.target_name.assign(raw_name, strnlen(raw_name, kTargetNameSize));
  const uint32_t target_size = cbx_get_u32(t + 266);
  const uint32_t elements = cbx_get_u32(t + 270);
  at += kTargetPrefixSize;
  if (target_size != suffix_at - at) {
    return bad(name, at - 8, "dwTargetSize " + std::to_string(target_size) + " does not match the " +
                                 std::to_string(suffix_at - at) + " bytes that follow");
  }
  if (elements == 0 || elements > 64) return bad(name, at - 4, std::to_string(elements) + " elements (1..64 allowed)");
  for (uint32_t i = 0; i < elements; ++i) {
    if (at + kElementHeaderSize > suffix_at) return bad(name, at, "element " + std::to_string(i) + " header runs past the end");
    DfuElement element;
    element.address = cbx_get_u32(p + at);
    const uint32_t size = cbx_get_u32(p + at + 4);
    at += kElementHeaderSize;
    if (size > suffix_at - at) return bad(name, at - 4, "element " + std::to_string(i) + " size runs past the end");
    element.data.assign(p + at, p + at + size);
    at += size;
    image.elements.push_back(std::move(element));
  }
  if (at != suffix_at) return bad(name, at, "extra bytes after the last element");
  return image;
}

Result<DfuImage> DfuFile::load(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return make_error(Errc::kBadArgument, path + ": cannot open");
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return parse(bytes, path);
}

std::vector<uint8_t> DfuFile::write(const DfuImage& image) {
  std::vector<uint8_t> out;
  put_text(out, "DfuSe", 5);
  out.push_back(0x01);
  cbx_put_u32(grow(out, 4), 0);  // DFUImageSize, patched below
  out.push_back(1);
  put_text(out, "Target", 6);
  out.push_back(image.alt_setting);
  cbx_put_u32(grow(out, 4), image.target_name.empty() ? 0u : 1u);
  const size_t name_length = std::min(image.target_name.size(), kTargetNameSize - 1);
  put_text(out, image.target_name.data(), name_length);
  out.resize(out.size() + kTargetNameSize - name_length, 0);
  size_t target_size = 0;
  for (const auto& e : image.elements) target_size += kElementHeaderSize + e.data.size();
  cbx_put_u32(grow(out, 4), static_cast<uint32_t>(target_size));
  cbx_put_u32(grow(out, 4), static_cast<uint32_t>(image.elements.size()));
  for (const auto& e : image.elements) {
    cbx_put_u32(grow(out, 4), e.address);
    cbx_put_u32(grow(out, 4), static_cast<uint32_t>(e.data.size()));
    out.insert(out.end(), e.data.begin(), e.data.end());
  }
  const uint32_t body = static_cast<uint32_t>(out.size());
  cbx_put_u32(out.data() + 6, body);
  cbx_put_u16(grow(out, 2), image.bcd_device);
  cbx_put_u16(grow(out, 2), image.pid);
  cbx_put_u16(grow(out, 2), image.vid);
  cbx_put_u16(grow(out, 2), 0x011A);
  put_text(out, "UFD", 3);
  out.push_back(static_cast<uint8_t>(kSuffixSize));
  const uint32_t crc = crc32(out);  // over everything before it
  cbx_put_u32(grow(out, 4), crc);
  return out;
}

}  // namespace cathbox::device
