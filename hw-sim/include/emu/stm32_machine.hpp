#pragma once
// The emulated STM32F411: a Cortex-M4F on the Unicorn engine running a firmware image as
// flashed (flash at 0x08000000, 128 KiB SRAM, system memory with the unique ID), with the board
// models written for this project from RM0383 and the Cortex-M4 user guide: the NVIC and
// SysTick (exception entry and return are done here: Unicorn leaves them to the board), RCC,
// PWR, FLASH, GPIO A-C, EXTI/SYSCFG, TIM2-5, ADC1, IWDG and DBGMCU (stm32_register_table.cpp, stm32_peripherals.cpp), and
// the USB OTG FS device core (otg_fs.hpp). Time is the CPU's: one instruction = one cycle at
// 96 MHz (SYSCLK from the PLL); run(cycles) executes that many, or sleeps (WFI) until an
// interrupt is due. An access to a register no model implements stops the machine with an
// error naming the address and the missing model.
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "emu/otg_fs.hpp"

struct uc_struct;

namespace cathbox::emu {

struct Stm32Inputs {
  bool estop_open = false;            // PB8: the E-stop loop is open (pressed / wire cut)
  std::array<int64_t, 2> encoder{};   // TIM2 / TIM3 counts from the encoders
  std::array<int16_t, 2> current_mA{};
  uint16_t supply_mV = 24000;
  bool crystal_fails = false;         // the 25 MHz HSE never starts: HSERDY stays 0 (set before boot)
};

struct Stm32Outputs {
  std::array<int16_t, 2> drive_permille{};  // TIM4 CH1/CH2 duty with PB12/PB13 direction, PB14 enable
  bool led_on = false;
};

class Stm32Machine {
 public:
  static constexpr uint64_t kSysclk_Hz = 96'000'000;
  static constexpr uint32_t kFlashBase = 0x08000000u;
  static constexpr uint32_t kFlashSize = 512u * 1024u;
  static constexpr uint32_t kSramBase = 0x20000000u;
  static constexpr uint32_t kSramSize = 128u * 1024u;
  static constexpr uint32_t kSysmemBase = 0x1FFF0000u;
  static constexpr uint32_t kBootloaderEntry = kSysmemBase + 0x100u;  // the emulated ROM's entry

  Stm32Machine();
  ~Stm32Machine();
  Stm32Machine(const Stm32Machine&) = delete;
  Stm32Machine& operator=(const Stm32Machine&) = delete;

  // Writes `image` at the start of flash (the rest stays erased) and resets.
  void load_flash(std::span<const uint8_t> image);
  [[nodiscard]] std::vector<uint8_t> flash() const;
  void write_flash(uint32_t offset, std::span<const uint8_t> bytes);
  // Power-on or system reset: peripherals to their reset values, the core from the vector table.
  // SRAM keeps its contents (a system reset does not clear it).
  void reset();

  // Runs `cycles` CPU cycles (or sleeps through them). Returns false once the machine stopped on
  // an error (error() says which), or entered the ROM bootloader (in_bootloader()).
  bool run(uint64_t cycles);
  [[nodiscard]] const std::string& error() const { return error_; }
  [[nodiscard]] bool in_bootloader() const { return in_bootloader_; }
  [[nodiscard]] uint64_t cycles() const { return cycles_; }
  [[nodiscard]] uint32_t pc() const;
  [[nodiscard]] uint64_t instructions() const { return instructions_; }
  [[nodiscard]] uint64_t resets() const { return resets_; }
  [[nodiscard]] uint64_t watchdog_resets() const { return watchdog_resets_; }
  // Instructions of the last completed SysTick handler, and the most since reset.
  [[nodiscard]] uint64_t tick_instructions_last() const { return tick_last_; }
  [[nodiscard]] uint64_t tick_instructions_max() const { return tick_max_; }
  void reset_tick_instructions_max() { tick_max_ = 0; }
  // SysTick handlers completed since the machine was made.
  [[nodiscard]] uint64_t ticks() const { return ticks_; }

  Stm32Inputs& inputs() { return inputs_; }
  [[nodiscard]] Stm32Outputs outputs() const;
  OtgFs& otg() { return otg_; }
  // --trace-mmio: one line per register access (peripheral, register, value) to `sink`.
  void set_trace(std::function<void(const std::string&)> sink) { trace_ = std::move(sink); }

  // Register models (stm32_peripherals.cpp); public for the dispatch callbacks.
  struct Peripherals;
  uint64_t periph_read(uint32_t address, unsigned size);
  void periph_write(uint32_t address, unsigned size, uint32_t value);
  uint64_t scs_read(uint32_t address, unsigned size);
  void scs_write(uint32_t address, unsigned size, uint32_t value);
  uint64_t otg_read(uint32_t address, unsigned size);
  void otg_write(uint32_t address, unsigned size, uint32_t value);
  void on_block(uint64_t address, uint32_t size);
  void on_return_trampoline();
  void on_bootloader_entry();
  void on_wfi(uint64_t address);
  bool on_flash_write(uint64_t address, int size, int64_t value);
  void on_interrupt(uint32_t intno);
  void fail(const std::string& message);
  void flash_store(uint32_t address, int size, uint32_t value);  // programming: bits 1 -> 0 only
  void flash_erase(uint32_t offset, uint32_t size);
  void trace(const char* peripheral, const char* reg, uint32_t address, bool write, uint32_t value);

 private:
  struct Frame {
    uint32_t exception;   // 15 = SysTick, 16 + n = IRQ n
    int priority;
    uint64_t start_instructions;
    std::array<uint32_t, 32> fp;  // S0..S31
    uint32_t fpscr;
  };
  void map_memory();
  void hook_wfi();
  void take_interrupts();
  [[nodiscard]] int pending_exception(int& priority) const;
  [[nodiscard]] int exception_priority(uint32_t exception) const;
  void enter(uint32_t exception, int priority);
  void advance_timers(uint64_t now);
  [[nodiscard]] uint64_t cycles_to_systick() const;
  [[nodiscard]] uint32_t instructions_in_block(uint64_t address, uint32_t size) const;
  [[nodiscard]] uint32_t reg(int id) const;
  void set_reg(int id, uint32_t value);

  struct Memory;
  uc_struct* uc_ = nullptr;
  std::unique_ptr<Peripherals> p_;
  std::unique_ptr<Memory> mem_;
  OtgFs otg_;
  Stm32Inputs inputs_;
  std::vector<uint8_t> flash_;
  std::string error_;
  std::function<void(const std::string&)> trace_;
  bool stopped_ = false;
  bool in_bootloader_ = false;
  bool sleeping_ = false;
  bool reset_requested_ = false;
  uint64_t cycles_ = 0;
  uint64_t instructions_ = 0;
  uint64_t budget_end_ = 0;
  uint32_t budget_stop_pc_ = 0;  // the block a slice's budget stopped in front of, else 0
  bool flash_stall_ = false;     // that block is in flash while the flash is busy: the CPU waits
  uint32_t wfi_pc_ = 0;          // the WFI a slice stopped at, else 0
  uint64_t resets_ = 0;
  uint64_t watchdog_resets_ = 0;
  uint64_t tick_last_ = 0;
  uint64_t tick_max_ = 0;
  uint64_t ticks_ = 0;
  std::vector<Frame> active_;
  // SCS state: NVIC, SysTick, SCB.
  std::array<uint32_t, 3> nvic_enabled_{};
  std::array<uint32_t, 3> nvic_pending_{};
  std::array<uint8_t, 96> nvic_priority_{};
  uint32_t systick_csr_ = 0, systick_rvr_ = 0, systick_cvr_ = 0;
  bool systick_pending_ = false;
  uint32_t vtor_ = 0, shpr3_ = 0, cpacr_ = 0, aircr_ = 0;
  uint32_t dbgmcu_apb1_fz_ = 0;
  uint64_t timer_cycles_ = 0;  // cycles already given to SysTick and the peripherals' clocks
  mutable std::unordered_map<uint64_t, uint32_t> block_sizes_;  // (address, bytes) -> instructions
  uint64_t hooks_[5]{};
  std::vector<uint64_t> wfi_hooks_;  // one code hook per WFI instruction in flash
};

}  // namespace cathbox::emu
