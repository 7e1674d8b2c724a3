// The STM32F411 peripherals the firmware image touches, from RM0383: RCC, PWR, FLASH
// interface, GPIOA-C, SYSCFG, EXTI, TIM2-5, ADC1 and IWDG. A register not in the table below is
// not modelled: an access to it stops the machine naming the address and the peripheral.
#include "stm32_peripherals.hpp"

#include <algorithm>
#include <cstdio>

namespace cathbox::emu {
namespace {

constexpr uint32_t kRcc = 0x40023800u, kFlash = 0x40023C00u, kPwr = 0x40007000u, kIwdg = 0x40003000u;
constexpr uint32_t kAdc = 0x40012000u, kSyscfg = 0x40013800u, kExti = 0x40013C00u;
constexpr uint32_t kGpio[3] = {0x40020000u, 0x40020400u, 0x40020800u};
constexpr uint32_t kTim[4] = {0x40000000u, 0x40000400u, 0x40000800u, 0x40000C00u};
constexpr uint64_t kCyclesPerUs = Stm32Machine::kSysclk_Hz / 1'000'000u;
constexpr uint64_t kLsi_Hz = 32'000;  // nominal; the chip's LSI is 17..47 kHz (datasheet)
// Board constants of firmware/ports/stm32f411/board.h (the analogue front end).
constexpr int kAdcVref_mV = 3300, kCurrentZero_mV = 1650, kCurrent_mV_per_A = 500, kSupplyDivider = 11;
constexpr uint32_t kPwmEnablePin = 14, kDirInsertionPin = 12, kDirRotationPin = 13, kEstopPin = 8, kLedPin = 13;

struct Block {
  uint32_t base;
  const char* name;
};
// RM0383 table 1 (memory map), the APB1/APB2/AHB1 blocks.
constexpr Block kBlocks[] = {
    {0x40000000u, "TIM2"},   {0x40000400u, "TIM3"},   {0x40000800u, "TIM4"},    {0x40000C00u, "TIM5"},
    {0x40002800u, "RTC"},    {0x40002C00u, "WWDG"},   {0x40003000u, "IWDG"},    {0x40003400u, "I2S2ext"},
    {0x40003800u, "SPI2"},   {0x40003C00u, "SPI3"},   {0x40004000u, "I2S3ext"}, {0x40004400u, "USART2"},
    {0x40005400u, "I2C1"},   {0x40005800u, "I2C2"},   {0x40005C00u, "I2C3"},    {0x40007000u, "PWR"},
    {0x40010000u, "TIM1"},   {0x40011000u, "USART1"}, {0x40011400u, "USART6"},  {0x40012000u, "ADC1"},
    {0x40012C00u, "SDIO"},   {0x40013000u, "SPI1"},   {0x40013400u, "SPI4"},    {0x40013800u, "SYSCFG"},
    {0x40013C00u, "EXTI"},   {0x40014000u, "TIM9"},   {0x40014400u, "TIM10"},   {0x40014800u, "TIM11"},
    {0x40015000u, "SPI5"},   {0x40020000u, "GPIOA"},  {0x40020400u, "GPIOB"},   {0x40020800u, "GPIOC"},
    {0x40020C00u, "GPIOD"},  {0x40021000u, "GPIOE"},  {0x40021C00u, "GPIOH"},   {0x40023000u, "CRC"},
    {0x40023800u, "RCC"},    {0x40023C00u, "FLASH"},  {0x40026000u, "DMA1"},    {0x40026400u, "DMA2"},
    {0x50000000u, "OTG_FS"}, {0xE000E000u, "SCS"},    {0xE0042000u, "DBGMCU"},
};

const char* block_name(uint32_t address) {
  for (const Block& b : kBlocks) {
    if (address >= b.base && address < b.base + 0x400u) return b.name;
  }
  if (address >= 0x50000000u && address < 0x50040000u) return "OTG_FS";
  if (address >= 0xE000E000u && address < 0xE000F000u) return "SCS";
  return "reserved";
}

// Flash sectors of the STM32F411xE (RM0383 3.3): 4 x 16 KiB, 64 KiB, 3 x 128 KiB; erase times
// (typical, x32) as the emulated ROM bootloader reports them in bwPollTimeout.
struct Sector {
  uint32_t offset, size;
  uint64_t erase_ms;
};
constexpr Sector kSectors[8] = {{0x00000, 0x4000, 250},  {0x04000, 0x4000, 250},  {0x08000, 0x4000, 250},
                                {0x0C000, 0x4000, 250},  {0x10000, 0x10000, 550}, {0x20000, 0x20000, 1000},
                                {0x40000, 0x20000, 1000}, {0x60000, 0x20000, 1000}};
constexpr uint64_t kProgramWord_us = 16;
constexpr uint64_t kBusyPoll_cycles = 10 * kCyclesPerUs;

}  // namespace

Stm32Machine::Peripherals::Peripherals() {
  auto add = [&](uint32_t address, const char* peripheral, const char* name, uint32_t reset) {
    registers[address] = {peripheral, name, reset};
  };
  add(kRcc + 0x00, "RCC", "CR", 0x00000083u);
  add(kRcc + 0x04, "RCC", "PLLCFGR", 0x24003010u);
  add(kRcc + 0x08, "RCC", "CFGR", 0);
  add(kRcc + 0x30, "RCC", "AHB1ENR", 0);
  add(kRcc + 0x34, "RCC", "AHB2ENR", 0);
  add(kRcc + 0x40, "RCC", "APB1ENR", 0);
  add(kRcc + 0x44, "RCC", "APB2ENR", 0);
  add(kRcc + 0x74, "RCC", "CSR", 0x0E000000u);
  add(kPwr + 0x00, "PWR", "CR", 0x0000C000u);
  add(kFlash + 0x00, "FLASH", "ACR", 0);
  add(kFlash + 0x04, "FLASH", "KEYR", 0);
  add(kFlash + 0x0C, "FLASH", "SR", 0);
  add(kFlash + 0x10, "FLASH", "CR", 0x80000000u);
  add(kFlash + 0x14, "FLASH", "OPTCR", 0x0FFFAAEDu);
  static const char* const gpio_names[3] = {"GPIOA", "GPIOB", "GPIOC"};
  static const char* const gpio_regs[10] = {"MODER", "OTYPER", "OSPEEDR", "PUPDR", "IDR", "ODR", "BSRR", "LCKR", "AFRL", "AFRH"};
  const uint32_t moder[3] = {0xA8000000u, 0x00000280u, 0};
  const uint32_t ospeedr[3] = {0x0C000000u, 0x000000C0u, 0};
  const uint32_t pupdr[3] = {0x64000000u, 0x00000100u, 0};
  for (int g = 0; g < 3; ++g) {
    for (uint32_t r = 0; r < 10; ++r) {
      const uint32_t reset = r == 0 ? moder[g] : r == 2 ? ospeedr[g] : r == 3 ? pupdr[g] : 0u;
      add(kGpio[g] + 4 * r, gpio_names[g], gpio_regs[r], reset);
    }
  }
  static const char* const tim_names[4] = {"TIM2", "TIM3", "TIM4", "TIM5"};
  struct TimReg { uint32_t offset; const char* name; };
  static const TimReg tim_regs[] = {{0x00, "CR1"}, {0x08, "SMCR"}, {0x0C, "DIER"}, {0x10, "SR"}, {0x14, "EGR"},
                                    {0x18, "CCMR1"}, {0x20, "CCER"}, {0x24, "CNT"}, {0x28, "PSC"}, {0x2C, "ARR"},
                                    {0x34, "CCR1"}, {0x38, "CCR2"}};
  for (int t = 0; t < 4; ++t) {
    for (const TimReg& r : tim_regs) add(kTim[t] + r.offset, tim_names[t], r.name, r.offset == 0x2C ? 0xFFFFFFFFu : 0u);
  }
  add(kAdc + 0x00, "ADC1", "SR", 0);
  add(kAdc + 0x04, "ADC1", "CR1", 0);
  add(kAdc + 0x08, "ADC1", "CR2", 0);
  add(kAdc + 0x10, "ADC1", "SMPR2", 0);
  add(kAdc + 0x38, "ADC1", "JSQR", 0);
  add(kAdc + 0x3C, "ADC1", "JDR1", 0);
  add(kAdc + 0x40, "ADC1", "JDR2", 0);
  add(kAdc + 0x44, "ADC1", "JDR3", 0);
  add(kAdc + 0x48, "ADC1", "JDR4", 0);
  add(kAdc + 0x304, "ADC", "CCR", 0);
  add(kIwdg + 0x0, "IWDG", "KR", 0);
  add(kIwdg + 0x4, "IWDG", "PR", 0);
  add(kIwdg + 0x8, "IWDG", "RLR", 0xFFFu);
  add(kIwdg + 0xC, "IWDG", "SR", 0);
  add(kExti + 0x00, "EXTI", "IMR", 0);
  add(kExti + 0x08, "EXTI", "RTSR", 0);
  add(kExti + 0x0C, "EXTI", "FTSR", 0);
  add(kExti + 0x14, "EXTI", "PR", 0);
  add(kSyscfg + 0x00, "SYSCFG", "MEMRMP", 0);
  for (uint32_t n = 0; n < 4; ++n) add(kSyscfg + 0x08 + 4 * n, "SYSCFG", "EXTICR", 0);
  reset();
}

void Stm32Machine::Peripherals::reset() {
  const uint32_t csr_flags = values.count(kRcc + 0x74) ? values[kRcc + 0x74] & 0xFE000000u : 0x0E000000u;
  values.clear();
  for (const auto& [address, r] : registers) values[address] = r.reset;
  values[kRcc + 0x74] = csr_flags;  // reset flags survive a system reset (cleared by RMVF)
  flash_unlocking = false;
  flash_busy_cycles = 0;
  iwdg_running = iwdg_unlocked = false;
  iwdg_cycles_left = 0;
  adc_busy_cycles = 0;
  encoder_base = {};
  tim5_base_cycles = 0;
}

uint32_t Stm32Machine::Peripherals::get(uint32_t address) const {
  const auto it = values.find(address);
  return it == values.end() ? 0u : it->second;
}

std::string Stm32Machine::Peripherals::unmodelled(uint32_t address, bool write) {
  char line[160];
  std::snprintf(line, sizeof line, "%s of 0x%08X: no model for this register of %s (hw-sim/README.md lists what is modelled)",
                write ? "write" : "read", address, block_name(address));
  return line;
}

uint32_t Stm32Machine::Peripherals::gpio_idr(const Stm32Machine& m, int g) {
  // IDR: outputs read back, inputs from the board.
  const uint32_t mode = values[kGpio[g]];
  const uint32_t pull = values[kGpio[g] + 0x0C];
  uint32_t v = 0;
  for (uint32_t pin = 0; pin < 16; ++pin) {
    const uint32_t md = (mode >> (2 * pin)) & 3u;
    bool level = ((pull >> (2 * pin)) & 3u) == 1u;  // pull-up; floating and pull-down read 0
    if (md == 1u) level = (values[kGpio[g] + 0x14] >> pin) & 1u;
    if (g == 1 && pin == kEstopPin) level = m.inputs_.estop_open;
    v |= (level ? 1u : 0u) << pin;
  }
  return v;
}

uint32_t Stm32Machine::Peripherals::timer_count(const Stm32Machine& m, int t) {
  const uint32_t stored = values[kTim[t] + 0x24];
  if (t == 0 || t == 1) {  // encoder mode: the model's counts from where CNT was set
    const bool counting = (values[kTim[t]] & 1u) && (values[kTim[t] + 0x08] & 7u) == 3u;
    if (!counting) return stored;
    const auto count = static_cast<uint64_t>(encoder_base[static_cast<size_t>(t)] + m.inputs_.encoder[static_cast<size_t>(t)]);
    const uint64_t arr = values[kTim[t] + 0x2C];
    return static_cast<uint32_t>(arr == 0xFFFFFFFFu ? count : count % (arr + 1u));
  }
  if (t == 3 && (values[kTim[3]] & 1u)) {  // TIM5: the time base, from the CPU's cycles
    return static_cast<uint32_t>((m.cycles_ - tim5_base_cycles) / (values[kTim[3] + 0x28] + 1u));
  }
  return stored;
}

bool Stm32Machine::Peripherals::read(Stm32Machine& m, uint32_t address, unsigned size, uint32_t& v) {
  if (registers.find(address & ~3u) == registers.end()) return false;
  const uint32_t a = address & ~3u;
  v = values[a];
  for (int g = 0; g < 3; ++g) {
    if (a == kGpio[g] + 0x10) v = gpio_idr(m, g);
  }
  for (int t = 0; t < 4; ++t) {
    if (a == kTim[t] + 0x24) v = timer_count(m, t);
  }
  if (a == kFlash + 0x0C) {
    v = (values[a] & 0xF3u) | (flash_busy_cycles > 0 ? (1u << 16) : 0u);
    // A poll of BSY while the flash is busy costs 10 us of emulated time (silicon: a few
    // cycles), so a 1 s sector erase is 100 000 polls, not 20 million (hw-sim/README.md).
    if (flash_busy_cycles > 0) m.cycles_ += std::min<uint64_t>(flash_busy_cycles, kBusyPoll_cycles);
  }
  if (a == kIwdg + 0x0C) v = 0;  // PR/RLR updates take effect within the write (silicon: ~5 LSI periods)
  m.trace(registers[a].peripheral, registers[a].name, address, false, v);
  if (size == 1) v = (v >> (8 * (address & 3u))) & 0xFFu;
  if (size == 2) v = (v >> (8 * (address & 2u))) & 0xFFFFu;
  return true;
}

bool Stm32Machine::Peripherals::write_clock_flash(Stm32Machine& m, uint32_t a, uint32_t v, uint32_t& r) {
  if (a == kRcc + 0x00) {  // CR: ready flags follow their enables (HSERDY only with a working crystal)
    r = (v & 0x0D0F00F9u) | 0x2u;
    if ((v & (1u << 16)) && !m.inputs().crystal_fails) r |= 1u << 17;
    if (v & (1u << 24)) r |= 1u << 25;
    return true;
  }
  if (a == kRcc + 0x08) {  // CFGR: SWS follows SW
    r = (v & ~0xCu) | ((v & 3u) << 2);
    return true;
  }
  if (a == kRcc + 0x74) {  // CSR: RMVF clears the reset flags
    r = (v & 1u) | ((v & (1u << 24)) ? 0u : (r & 0xFE000000u));
    return true;
  }
  if (a == kFlash + 0x04) {  // KEYR
    if (!flash_unlocking && v == 0x45670123u) {
      flash_unlocking = true;
    } else if (flash_unlocking && v == 0xCDEF89ABu) {
      values[kFlash + 0x10] &= ~(1u << 31);
      flash_unlocking = false;
    } else {
      flash_unlocking = false;  // a wrong sequence: locked until reset (silicon: also a bus error)
    }
    return true;
  }
  if (a == kFlash + 0x0C) {  // SR: error flags clear by writing 1
    r &= ~(v & 0xF3u);
    return true;
  }
  if (a == kFlash + 0x10) {  // CR
    if (r & (1u << 31)) return true;  // locked: ignored
    r = v & 0x8101037Fu;
    if ((v & (1u << 16)) && (v & 2u)) {  // STRT with SER: sector erase
      const uint32_t snb = (v >> 3) & 0xFu;
      if (snb >= 8) {
        values[kFlash + 0x0C] |= 1u << 7;  // PGSERR
      } else {
        m.flash_erase(kSectors[snb].offset, kSectors[snb].size);
        flash_busy_cycles = kSectors[snb].erase_ms * 1000u * kCyclesPerUs;
      }
    }
    return true;
  }
  return false;
}

bool Stm32Machine::Peripherals::write_gpio_timer(Stm32Machine& m, uint32_t a, uint32_t v, uint32_t& r) {
  for (int g = 0; g < 3; ++g) {
    if (a == kGpio[g] + 0x18) {  // BSRR: set wins over reset
      uint32_t& odr = values[kGpio[g] + 0x14];
      odr = ((odr & ~(v >> 16)) | (v & 0xFFFFu)) & 0xFFFFu;
      return true;
    }
    if (a == kGpio[g] + 0x10) return true;  // IDR is read-only
  }
  for (int t = 0; t < 4; ++t) {
    if (a == kTim[t] + 0x24) {  // CNT written: the count continues from there
      if (t < 2) encoder_base[static_cast<size_t>(t)] = static_cast<int64_t>(v) - m.inputs_.encoder[static_cast<size_t>(t)];
      if (t == 3) tim5_base_cycles = m.cycles_ - static_cast<uint64_t>(v) * (values[kTim[3] + 0x28] + 1u);
      r = v;
      return true;
    }
    if (a == kTim[t] + 0x14 && (v & 1u)) {  // EGR.UG: counter to 0, prescaler and preloads loaded
      if (t < 2) encoder_base[static_cast<size_t>(t)] = -m.inputs_.encoder[static_cast<size_t>(t)];
      if (t == 3) tim5_base_cycles = m.cycles_;
      return true;
    }
    if (a == kTim[t] + 0x00 && t == 3 && !(r & 1u) && (v & 1u)) tim5_base_cycles = m.cycles_ - static_cast<uint64_t>(values[kTim[3] + 0x24]) * (values[kTim[3] + 0x28] + 1u);
  }
  return false;
}

bool Stm32Machine::Peripherals::write_adc_iwdg_exti(uint32_t a, uint32_t v, uint32_t& r) {
  if (a == kAdc + 0x08) {  // CR2: JSWSTART starts the injected scan (about 12 us)
    r = v & ~(1u << 22);
    if ((v & (1u << 22)) && (v & 1u)) {
      adc_busy_cycles = 12u * kCyclesPerUs;
      values[kAdc] |= 1u << 3;  // JSTRT
    }
    return true;
  }
  if (a == kAdc + 0x00) {  // SR: rc_w0
    r &= v;
    return true;
  }
  if (a == kIwdg + 0x0) {  // KR
    const uint32_t key = v & 0xFFFFu;
    if (key == 0xCCCCu && !iwdg_running) {
      iwdg_running = true;
      iwdg_cycles_left = 0;
    }
    if (key == 0xCCCCu || key == 0xAAAAu) {
      const uint64_t divider = 4u << (values[kIwdg + 0x4] & 7u);
      iwdg_cycles_left = (values[kIwdg + 0x8] + 1u) * divider * (Stm32Machine::kSysclk_Hz / kLsi_Hz);
      iwdg_unlocked = false;
    }
    if (key == 0x5555u) iwdg_unlocked = true;
    return true;
  }
  if (a == kIwdg + 0x4 || a == kIwdg + 0x8) {
    if (iwdg_unlocked) r = v & (a == kIwdg + 0x4 ? 7u : 0xFFFu);
    return true;
  }
  if (a == kIwdg + 0xC) return true;
  if (a == kExti + 0x14) {  // PR: rc_w1
    r &= ~v;
    return true;
  }
  return false;
}

bool Stm32Machine::Peripherals::write(Stm32Machine& m, uint32_t address, unsigned size, uint32_t v) {
  const uint32_t a = address & ~3u;
  const auto it = registers.find(a);
  if (it == registers.end() || size != 4) return false;
  m.trace(it->second.peripheral, it->second.name, address, true, v);
  uint32_t& r = values[a];
  if (write_clock_flash(m, a, v, r) || write_gpio_timer(m, a, v, r) || write_adc_iwdg_exti(a, v, r)) return true;
  r = v;
  return true;
}

void Stm32Machine::Peripherals::update_irqs(Stm32Machine& m) {
  const bool level = m.inputs_.estop_open;
  const bool mapped_b = ((values[kSyscfg + 0x10] >> (4u * (kEstopPin % 4u))) & 0xFu) == 1u;
  if (mapped_b && level != estop_level) {
    const uint32_t bit = 1u << kEstopPin;
    if ((level && (values[kExti + 0x08] & bit)) || (!level && (values[kExti + 0x0C] & bit))) values[kExti + 0x14] |= bit;
  }
  estop_level = level;
  if (values[kExti + 0x14] & values[kExti] & 0x3E0u) m.nvic_pending_[0] |= 1u << 23;  // EXTI9_5
}

void Stm32Machine::Peripherals::advance(Stm32Machine& m, uint64_t cycles) {
  if (flash_busy_cycles > 0) flash_busy_cycles = cycles >= flash_busy_cycles ? 0 : flash_busy_cycles - cycles;
  if (adc_busy_cycles > 0) {
    if (cycles >= adc_busy_cycles) {
      adc_busy_cycles = 0;
      auto raw = [](int mv) { return static_cast<uint32_t>(std::clamp(mv, 0, kAdcVref_mV) * 4095 / kAdcVref_mV); };
      for (size_t i = 0; i < 2; ++i) {
        values[kAdc + 0x3C + 4u * i] = raw(kCurrentZero_mV + m.inputs_.current_mA[i] * kCurrent_mV_per_A / 1000);
      }
      values[kAdc + 0x44] = raw(m.inputs_.supply_mV / kSupplyDivider);
      values[kAdc + 0x48] = values[kAdc + 0x44];
      values[kAdc] = (values[kAdc] | (1u << 2)) & ~(1u << 3);  // JEOC
    } else {
      adc_busy_cycles -= cycles;
    }
  }
  if (iwdg_running) {
    if (cycles >= iwdg_cycles_left) {
      values[kRcc + 0x74] |= 1u << 29;  // IWDGRSTF
      ++m.watchdog_resets_;
      m.reset_requested_ = true;
      iwdg_running = false;
    } else {
      iwdg_cycles_left -= cycles;
    }
  }
}

uint64_t Stm32Machine::Peripherals::cycles_to_event() const {
  uint64_t next = UINT64_MAX;
  if (flash_busy_cycles > 0) next = std::min(next, flash_busy_cycles);
  if (adc_busy_cycles > 0) next = std::min(next, adc_busy_cycles);
  if (iwdg_running) next = std::min(next, iwdg_cycles_left);
  return next;
}

bool Stm32Machine::Peripherals::flash_program(Stm32Machine& m, uint32_t address, int size, uint32_t value) {
  const uint32_t cr = values[kFlash + 0x10];
  uint32_t& sr = values[kFlash + 0x0C];
  if ((cr & (1u << 31)) || !(cr & 1u)) {
    sr |= (cr & (1u << 31)) ? (1u << 4) : (1u << 7);  // WRPERR locked, PGSERR without PG
    return true;                                      // the write does not reach the array
  }
  const int psize = 1 << ((cr >> 8) & 3u);
  if (size != psize) {
    sr |= 1u << 6;  // PGPERR: the access size is not PSIZE
    return true;
  }
  m.flash_store(address, size, value);
  flash_busy_cycles = kProgramWord_us * kCyclesPerUs;
  return true;
}

Stm32Outputs Stm32Machine::Peripherals::outputs() const {
  Stm32Outputs out;
  const uint32_t odr_b = get(kGpio[1] + 0x14);
  const bool enabled = (odr_b >> kPwmEnablePin) & 1u;
  const uint32_t arr = get(kTim[2] + 0x2C);
  const bool running = (get(kTim[2]) & 1u) && arr > 0 && arr != 0xFFFFFFFFu;
  const uint32_t ccer = get(kTim[2] + 0x20);
  const uint32_t ccr[2] = {get(kTim[2] + 0x34), get(kTim[2] + 0x38)};
  const uint32_t dir_pins[2] = {kDirInsertionPin, kDirRotationPin};
  for (size_t i = 0; i < 2; ++i) {
    if (!enabled || !running || !(ccer & (1u << (4 * i)))) continue;
    const int32_t permille = static_cast<int32_t>(std::min<uint64_t>(1000, uint64_t{ccr[i]} * 1000u / (arr + 1u)));
    out.drive_permille[i] = static_cast<int16_t>(((odr_b >> dir_pins[i]) & 1u) ? -permille : permille);
  }
  out.led_on = !((get(kGpio[2] + 0x14) >> kLedPin) & 1u);
  return out;
}

}  // namespace cathbox::emu
