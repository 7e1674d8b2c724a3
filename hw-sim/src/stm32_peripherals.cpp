// The behaviour of the STM32F411 peripherals the firmware image touches (RM0383): reads that
// show the board (GPIO inputs, encoder and time-base counters, flash status), writes with an
// effect (clocks, flash unlock/erase/program, GPIO set/reset, timers, ADC, IWDG, EXTI), the
// E-stop interrupt, time passing and the drive outputs. The register table: stm32_register_table.cpp.
#include "stm32_peripherals.hpp"

#include <algorithm>

namespace cathbox::emu {
namespace {

constexpr uint64_t kCyclesPerUs = Stm32Machine::kSysclk_Hz / 1'000'000u;
constexpr uint64_t kLsi_Hz = 32'000;  // nominal; the chip's LSI is 17..47 kHz (datasheet)
// Board constants of firmware/ports/stm32f411/board.h (the analogue front end).
constexpr int kAdcVref_mV = 3300, kCurrentZero_mV = 1650, kCurrent_mV_per_A = 500, kSupplyDivider = 11;
constexpr uint32_t kPwmEnablePin = 14, kDirInsertionPin = 12, kDirRotationPin = 13, kEstopPin = 8, kLedPin = 13;

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
