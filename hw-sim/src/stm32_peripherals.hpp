#pragma once
// The STM32F411's peripherals behind the Cortex-M4 (RM0383): the registers the firmware image
// touches, each with its reset value and behaviour. Private to hw-sim (stm32_machine.cpp).
#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>

#include "emu/stm32_machine.hpp"

namespace cathbox::emu {

struct Stm32Machine::Peripherals {
  // RM0383 table 1 (memory map): the modelled blocks' base addresses.
  static constexpr uint32_t kRcc = 0x40023800u, kFlash = 0x40023C00u, kPwr = 0x40007000u, kIwdg = 0x40003000u;
  static constexpr uint32_t kAdc = 0x40012000u, kSyscfg = 0x40013800u, kExti = 0x40013C00u;
  static constexpr uint32_t kGpio[3] = {0x40020000u, 0x40020400u, 0x40020800u};
  static constexpr uint32_t kTim[4] = {0x40000000u, 0x40000400u, 0x40000800u, 0x40000C00u};

  struct Register {
    const char* peripheral;
    const char* name;
    uint32_t reset;
  };
  Peripherals();  // the register table (stm32_register_table.cpp)
  void reset();
  bool read(Stm32Machine& m, uint32_t address, unsigned size, uint32_t& value);
  bool write(Stm32Machine& m, uint32_t address, unsigned size, uint32_t value);
  // The register-specific behaviour of a write, by block; false: a plain store.
  bool write_clock_flash(Stm32Machine& m, uint32_t address, uint32_t value, uint32_t& reg);
  bool write_gpio_timer(Stm32Machine& m, uint32_t address, uint32_t value, uint32_t& reg);
  bool write_adc_iwdg_exti(uint32_t address, uint32_t value, uint32_t& reg);
  uint32_t gpio_idr(const Stm32Machine& m, int port);
  uint32_t timer_count(const Stm32Machine& m, int timer);
  void update_irqs(Stm32Machine& m);
  void advance(Stm32Machine& m, uint64_t cycles);
  [[nodiscard]] uint64_t cycles_to_event() const;
  bool flash_program(Stm32Machine& m, uint32_t address, int size, uint32_t value);
  [[nodiscard]] Stm32Outputs outputs() const;
  // "no model for 0x40013000 (SPI1 ...)": the address and the peripheral whose model is missing.
  [[nodiscard]] static std::string unmodelled(uint32_t address, bool write);

  std::unordered_map<uint32_t, Register> registers;
  std::unordered_map<uint32_t, uint32_t> values;
  uint32_t& at(uint32_t address) { return values[address]; }
  [[nodiscard]] uint32_t get(uint32_t address) const;

  bool flash_unlocking = false;
  uint64_t flash_busy_cycles = 0;
  bool iwdg_running = false;
  bool iwdg_unlocked = false;
  uint64_t iwdg_cycles_left = 0;
  uint64_t adc_busy_cycles = 0;
  bool estop_level = false;
  std::array<int64_t, 2> encoder_base{};
  uint64_t tim5_base_cycles = 0;
};

}  // namespace cathbox::emu
