#include "emu/flash_memory.hpp"

#include <algorithm>

#include "protocol/cbx_bytes.h"
namespace cathbox::emu {

FlashMemory::FlashMemory() {
  uint32_t at = kBase;
  const auto add = [&](int count, uint32_t size, uint32_t erase_ms) {
    for (int i = 0; i < count; ++i, at += size) sectors_.push_back({at, size, erase_ms});
  };
  add(4, 16u * 1024u, 250);
  add(1, 64u * 1024u, 550);
  add(3, 128u * 1024u, 1000);
  bytes_.assign(at - kBase, 0xFF);
}

std::string FlashMemory::layout_name() const { return "@Internal Flash  /0x08000000/04*016Kg,01*064Kg,03*128Kg"; }

int FlashMemory::sector_at(uint32_t address) const {
  for (size_t i = 0; i < sectors_.size(); ++i) {
    if (address >= sectors_[i].address && address - sectors_[i].address < sectors_[i].size) return static_cast<int>(i);
  }
  return -1;
}

bool FlashMemory::contains(uint32_t address, size_t length) const {
  return address >= kBase && uint64_t{address} - kBase + length <= bytes_.size();
}

void FlashMemory::erase_sector(int index) {
  const FlashSector& s = sectors_.at(static_cast<size_t>(index));
  std::fill_n(bytes_.begin() + (s.address - kBase), s.size, uint8_t{0xFF});
}

bool FlashMemory::program(uint32_t address, std::span<const uint8_t> data) {
  if (!contains(address, data.size())) return false;
  const auto first = bytes_.begin() + (address - kBase);
  if (!std::all_of(first, first + static_cast<std::ptrdiff_t>(data.size()), [](uint8_t b) { return b == 0xFF; })) return false;
  std::copy(data.begin(), data.end(), first);
  return true;
}

bool FlashMemory::read(uint32_t address, std::span<uint8_t> out) const {
  if (!contains(address, out.size())) return false;
  std::copy_n(bytes_.begin() + (address - kBase), out.size(), out.begin());
  return true;
}

bool FlashMemory::application_valid() const {
  const uint32_t sp = cbx_get_u32(bytes_.data());
  const uint32_t reset = cbx_get_u32(bytes_.data() + 4);
  const bool sp_ok = sp > 0x20000000u && sp <= 0x20020000u;
  const bool reset_ok = (reset & 1u) != 0u && contains(reset & ~1u, 2);
  return sp_ok && reset_ok;
}

std::optional<cbx_image_info> FlashMemory::image_info() const {
  if (bytes_.size() < CBX_IMAGE_INFO_OFFSET + CBX_IMAGE_INFO_SIZE) return std::nullopt;
  cbx_image_info info;
  if (cbx_image_info_decode(bytes_.data() + CBX_IMAGE_INFO_OFFSET, CBX_IMAGE_INFO_SIZE, &info) != CBX_OK) {
    return std::nullopt;
  }
  return info;
}

void FlashMemory::load(uint32_t address, std::span<const uint8_t> data) {
  if (contains(address, data.size())) std::copy(data.begin(), data.end(), bytes_.begin() + (address - kBase));
}

}  // namespace cathbox::emu
