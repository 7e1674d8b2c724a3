#include "device/flasher.hpp"

#include <algorithm>
#include <cstdio>
#include <set>

#include "device/dfuse_client.hpp"
#include "device/dfuse_layout.hpp"
#include "protocol/cbx_bytes.h"
#include "protocol/cbx_protocol.h"

namespace cathbox::device {
namespace {

Error refuse(const std::string& what) { return make_error(Errc::kBadImage, "image refused, nothing erased: " + what); }

void report(const Flasher::Progress& progress, const std::string& step, size_t done, size_t total) {
  if (progress) progress(step, done, total);
}

}  // namespace

std::string Flasher::version_text(uint16_t bcd) {
  char text[16];
  std::snprintf(text, sizeof text, "%x.%x", bcd >> 8, bcd & 0xFFu);
  return text;
}

Status Flasher::check_image(const DfuImage& image, const FirmwareTarget& target) {
  if (image.vid != CBX_DFU_VID || image.pid != CBX_DFU_PID) {
    char text[96];
    std::snprintf(text, sizeof text, "built for USB %04x:%04x, not the STM32 ROM bootloader %04x:%04x", image.vid,
                  image.pid, CBX_DFU_VID, CBX_DFU_PID);
    return refuse(text);
  }
  if (image.target_name != target.name || image.alt_setting != 0) {
    return refuse("target '" + image.target_name + "' (alt " + std::to_string(image.alt_setting) + "), this box needs '" +
                  target.name + "' (alt 0)");
  }
  const unsigned major = ((image.bcd_device >> 12) & 0xFu) * 10u + ((image.bcd_device >> 8) & 0xFu);
  if (image.bcd_device == 0xFFFFu || major != target.firmware_major) {
    return refuse("firmware version " + version_text(image.bcd_device) + " speaks protocol v" + std::to_string(major) +
                  ", this host speaks v" + std::to_string(target.firmware_major));
  }
  const uint64_t flash_end = uint64_t{target.flash_base} + target.flash_size;
  std::vector<std::pair<uint64_t, uint64_t>> spans;
  for (const auto& e : image.elements) {
    const uint64_t end = uint64_t{e.address} + e.data.size();
    if (e.data.empty() || e.address < target.flash_base || end > flash_end) {
      return refuse("element at " + hex_address(e.address) + " of " + std::to_string(e.data.size()) + " bytes lies outside flash " +
                    hex_address(target.flash_base) + ".." + hex_address(static_cast<uint32_t>(flash_end - 1)));
    }
    spans.emplace_back(e.address, end);
  }
  std::sort(spans.begin(), spans.end());
  for (size_t i = 1; i < spans.size(); ++i) {
    if (spans[i].first < spans[i - 1].second) return refuse("elements overlap at " + hex_address(static_cast<uint32_t>(spans[i].first)));
  }
  // The vector table at the start of flash: initial stack pointer in RAM, reset handler a
  // Thumb address inside the image.
  const auto vectors = std::find_if(image.elements.begin(), image.elements.end(),
                                    [&](const DfuElement& e) { return e.address == target.flash_base; });
  if (vectors == image.elements.end() || vectors->data.size() < 8) {
    return refuse("no vector table at " + hex_address(target.flash_base));
  }
  const uint32_t sp = cbx_get_u32(vectors->data.data());
  const uint32_t reset = cbx_get_u32(vectors->data.data() + 4);
  if (sp <= target.ram_base || sp > target.ram_base + target.ram_size) {
    return refuse("initial stack pointer " + hex_address(sp) + " is not in this MCU's RAM (wrong target?)");
  }
  const bool in_image = std::any_of(spans.begin(), spans.end(), [&](const auto& s) {
    return (reset & ~1u) >= s.first && (reset & ~1u) < s.second;
  });
  if ((reset & 1u) == 0u || !in_image) return refuse("reset vector " + hex_address(reset) + " is not a Thumb address in the image");
  return Ok{};
}

Result<FlashReport> Flasher::flash(ControlTransfer& usb, const DfuImage& image, const FirmwareTarget& target,
                                   const Progress& progress) {
  auto checked = check_image(image, target);
  if (!checked) return checked.error();
  auto name = usb.alt_name(0);
  if (!name) return name.error();
  auto layout = DfuseLayout::parse(name.value());
  if (!layout) return layout.error();
  for (const auto& e : image.elements) {
    if (!layout.value().covers(e.address, static_cast<uint32_t>(e.data.size()))) {
      return refuse("element at " + hex_address(e.address) + " is not in the bootloader's writable memory '" + name.value() + "'");
    }
  }
  DfuseClient dfu(usb);
  auto idle = dfu.ensure_idle();
  if (!idle) return idle.error();

  // From here on the box's flash changes; a failure leaves the bootloader running.
  FlashReport result;
  std::set<uint32_t> sectors;
  for (const auto& e : image.elements) {
    for (uint64_t at = e.address; at < uint64_t{e.address} + e.data.size();) {
      const DfuseSector* s = layout.value().find(static_cast<uint32_t>(at));
      sectors.insert(s->address);
      at = uint64_t{s->address} + s->size;
    }
  }
  for (const uint32_t sector : sectors) {
    report(progress, "erase", result.sectors_erased, sectors.size());
    auto erased = dfu.erase(sector);
    if (!erased) return erased.error();
    ++result.sectors_erased;
  }
  const size_t total = image.total_bytes();
  for (const auto& e : image.elements) {
    for (size_t off = 0; off < e.data.size(); off += dfu.transfer_size()) {
      report(progress, "write", result.bytes_written, total);
      const size_t n = std::min<size_t>(dfu.transfer_size(), e.data.size() - off);
      auto written = dfu.write(e.address + static_cast<uint32_t>(off), std::span<const uint8_t>(e.data).subspan(off, n));
      if (!written) return written.error();
      result.bytes_written += n;
    }
  }
  for (const auto& e : image.elements) {
    report(progress, "verify", result.bytes_verified, total);
    auto back = dfu.read(e.address, e.data.size());
    if (!back) return back.error();
    const auto diff = std::mismatch(e.data.begin(), e.data.end(), back.value().begin());
    if (diff.first != e.data.end()) {
      const auto at = e.address + static_cast<uint32_t>(diff.first - e.data.begin());
      return make_error(Errc::kVerify, "verify failed at " + hex_address(at) + ": the bootloader is still running; flash again");
    }
    result.bytes_verified += e.data.size();
  }
  report(progress, "leave", 0, 1);
  auto left = dfu.leave(target.flash_base);
  if (!left) return left.error();
  return result;
}

}  // namespace cathbox::device
