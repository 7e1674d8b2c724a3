#pragma once
// The memory layout a DfuSe bootloader announces in its alternate setting's name, e.g.
// "@Internal Flash  /0x08000000/04*016Kg,01*064Kg,03*128Kg": sectors of a region, with
// their attributes (a readable, b erasable, c readable+erasable, d writeable, e readable+
// writeable, f erasable+writeable, g all three).
#include <cstdint>
#include <string>
#include <vector>

#include "device/result.hpp"

namespace cathbox::device {

struct DfuseSector {
  uint32_t address = 0;
  uint32_t size = 0;
  bool erasable = false;
  bool writable = false;
};

class DfuseLayout {
 public:
  [[nodiscard]] static Result<DfuseLayout> parse(const std::string& text);
  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] const std::vector<DfuseSector>& sectors() const { return sectors_; }
  // The sector holding address, or nullptr.
  [[nodiscard]] const DfuseSector* find(uint32_t address) const;
  // True when [address, address + size) lies in writable, erasable sectors.
  [[nodiscard]] bool covers(uint32_t address, uint32_t size) const;

 private:
  std::string name_;
  std::vector<DfuseSector> sectors_;
};

// A flash address as messages name it: "0x08004000".
[[nodiscard]] std::string hex_address(uint32_t address);

}  // namespace cathbox::device
