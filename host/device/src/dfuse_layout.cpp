#include "device/dfuse_layout.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <optional>

namespace cathbox::device {
namespace {

Error bad(const std::string& text, size_t at, const char* what) {
  return make_error(Errc::kDeviceError, "bootloader memory layout '" + text + "' at character " + std::to_string(at) + ": " + what);
}

// Parses an unsigned number at text[at] (base 0: 0x hex for addresses; base 10 for counts and
// sizes, whose leading zeros are not octal); advances at.
bool number(const std::string& text, size_t& at, uint64_t& value, int base) {
  const char* begin = text.c_str() + at;
  if (*begin < '0' || *begin > '9') return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtoull(begin, &end, base);
  if (end == begin || errno == ERANGE) return false;
  at += static_cast<size_t>(end - begin);
  return true;
}

// One sector group "COUNT*SIZE[ ][K|M|B]ATTR" at text[at]: its sectors appended from `address`
// on (which advances past them); advances at.
std::optional<Error> sector_group(const std::string& text, size_t& at, uint64_t& address, std::vector<DfuseSector>& out) {
  uint64_t count = 0;
  uint64_t size = 0;
  if (!number(text, at, count, 10) || count == 0 || count > 4096) return bad(text, at, "bad sector count");
  if (at >= text.size() || text[at] != '*') return bad(text, at, "expected '*'");
  ++at;
  // At most 32 bits before the K/M multiple, so that the multiple cannot wrap 64 bits.
  if (!number(text, at, size, 10) || size == 0 || size > 0xFFFFFFFFu) return bad(text, at, "bad sector size");
  if (at < text.size() && text[at] == ' ') ++at;
  if (at < text.size() && (text[at] == 'K' || text[at] == 'M' || text[at] == 'B')) {
    size *= text[at] == 'K' ? 1024u : (text[at] == 'M' ? 1024u * 1024u : 1u);
    ++at;
  }
  if (at >= text.size() || text[at] < 'a' || text[at] > 'g') return bad(text, at, "expected an attribute letter a..g");
  const int attr = text[at] - 'a' + 1;  // bit 0 readable, 1 erasable, 2 writeable
  ++at;
  for (uint64_t i = 0; i < count; ++i) {
    if (address + size > 0x100000000ull) return bad(text, at, "region runs past 4 GiB");
    out.push_back({static_cast<uint32_t>(address), static_cast<uint32_t>(size), (attr & 2) != 0, (attr & 4) != 0});
    address += size;
  }
  return std::nullopt;
}

// One region "/ADDRESS/GROUP[,GROUP...]" at text[at] (on its '/'); advances at.
std::optional<Error> region(const std::string& text, size_t& at, std::vector<DfuseSector>& out) {
  ++at;
  uint64_t address = 0;
  if (!number(text, at, address, 0) || address > 0xFFFFFFFFu) return bad(text, at, "bad region address");
  if (at >= text.size() || text[at] != '/') return bad(text, at, "expected '/' after the address");
  ++at;
  for (;;) {
    if (std::optional<Error> e = sector_group(text, at, address, out)) return e;
    if (at >= text.size() || text[at] != ',') return std::nullopt;
    ++at;
  }
}

}  // namespace

Result<DfuseLayout> DfuseLayout::parse(const std::string& text) {
  DfuseLayout layout;
  if (text.empty() || text[0] != '@') return bad(text, 0, "does not start with '@'");
  size_t at = text.find('/');
  if (at == std::string::npos) return bad(text, 0, "no '/' before the address");
  layout.name_ = text.substr(1, at - 1);
  while (!layout.name_.empty() && layout.name_.back() == ' ') layout.name_.pop_back();
  while (at < text.size() && text[at] == '/') {
    if (std::optional<Error> e = region(text, at, layout.sectors_)) return *e;
  }
  if (at != text.size()) return bad(text, at, "unexpected character");
  if (layout.sectors_.empty()) return bad(text, at, "no sectors");
  return layout;
}

const DfuseSector* DfuseLayout::find(uint32_t address) const {
  for (const auto& s : sectors_) {
    if (address >= s.address && address - s.address < s.size) return &s;
  }
  return nullptr;
}

bool DfuseLayout::covers(uint32_t address, uint32_t size) const {
  uint64_t at = address;
  const uint64_t end = static_cast<uint64_t>(address) + size;
  while (at < end) {
    const DfuseSector* s = find(static_cast<uint32_t>(at));
    if (s == nullptr || !s->erasable || !s->writable) return false;
    at = static_cast<uint64_t>(s->address) + s->size;
  }
  return true;
}

std::string hex_address(uint32_t address) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%08x", address);
  return text;
}

}  // namespace cathbox::device
