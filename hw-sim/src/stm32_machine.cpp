// The Cortex-M4 side of the emulated STM32F411: Unicorn, the memory map, reset, instruction
// counting, the run loop and flash. Exception entry and return are in
// stm32_exceptions.cpp, the register accesses in stm32_register_access.cpp, the peripherals in
// stm32_register_table.cpp (their registers) and stm32_peripherals.cpp (their behaviour).
#include "emu/stm32_machine.hpp"

#include <unicorn/unicorn.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "stm32_core.hpp"
#include "stm32_peripherals.hpp"

namespace cathbox::emu {

using stm32_core::kTrampoline;
using stm32_core::kXpsrThumb;

namespace {

constexpr uint32_t kSysmemSize = 0x8000u;
constexpr uint64_t kSliceCycles = 960;  // 10 us: the longest the CPU runs before interrupts are looked at

uint64_t periph_read_cb(uc_engine*, uint64_t offset, unsigned size, void* user) {
  return static_cast<Stm32Machine*>(user)->periph_read(0x40000000u + static_cast<uint32_t>(offset), size);
}
void periph_write_cb(uc_engine*, uint64_t offset, unsigned size, uint64_t value, void* user) {
  static_cast<Stm32Machine*>(user)->periph_write(0x40000000u + static_cast<uint32_t>(offset), size, static_cast<uint32_t>(value));
}
uint64_t scs_read_cb(uc_engine*, uint64_t offset, unsigned size, void* user) {
  return static_cast<Stm32Machine*>(user)->scs_read(0xE000E000u + static_cast<uint32_t>(offset), size);
}
void scs_write_cb(uc_engine*, uint64_t offset, unsigned size, uint64_t value, void* user) {
  static_cast<Stm32Machine*>(user)->scs_write(0xE000E000u + static_cast<uint32_t>(offset), size, static_cast<uint32_t>(value));
}
uint64_t dbg_read_cb(uc_engine*, uint64_t offset, unsigned size, void* user) {
  return static_cast<Stm32Machine*>(user)->scs_read(0xE0042000u + static_cast<uint32_t>(offset), size);
}
void dbg_write_cb(uc_engine*, uint64_t offset, unsigned size, uint64_t value, void* user) {
  static_cast<Stm32Machine*>(user)->scs_write(0xE0042000u + static_cast<uint32_t>(offset), size, static_cast<uint32_t>(value));
}
uint64_t otg_read_cb(uc_engine*, uint64_t offset, unsigned size, void* user) {
  return static_cast<Stm32Machine*>(user)->otg_read(static_cast<uint32_t>(offset), size);
}
void otg_write_cb(uc_engine*, uint64_t offset, unsigned size, uint64_t value, void* user) {
  static_cast<Stm32Machine*>(user)->otg_write(static_cast<uint32_t>(offset), size, static_cast<uint32_t>(value));
}
void block_cb(uc_engine*, uint64_t address, uint32_t size, void* user) {
  static_cast<Stm32Machine*>(user)->on_block(address, size);
}
void trampoline_cb(uc_engine*, uint64_t, uint32_t, void* user) { static_cast<Stm32Machine*>(user)->on_return_trampoline(); }
void bootloader_cb(uc_engine*, uint64_t, uint32_t, void* user) { static_cast<Stm32Machine*>(user)->on_bootloader_entry(); }
void wfi_cb(uc_engine*, uint64_t address, uint32_t, void* user) { static_cast<Stm32Machine*>(user)->on_wfi(address); }
bool flash_write_cb(uc_engine*, uc_mem_type, uint64_t address, int size, int64_t value, void* user) {
  return static_cast<Stm32Machine*>(user)->on_flash_write(address, size, value);
}
void intr_cb(uc_engine*, uint32_t intno, void* user) { static_cast<Stm32Machine*>(user)->on_interrupt(intno); }

bool is_wide(uint16_t halfword) { return (halfword >> 11) >= 0x1Du; }

}  // namespace

struct Stm32Machine::Memory {
  std::vector<uint8_t> sram = std::vector<uint8_t>(kSramSize, 0);
  std::vector<uint8_t> sysmem = std::vector<uint8_t>(kSysmemSize, 0xFF);
};

Stm32Machine::Stm32Machine() : p_(std::make_unique<Peripherals>()), mem_(std::make_unique<Memory>()), flash_(kFlashSize, 0xFF) {
  if (uc_open(UC_ARCH_ARM, static_cast<uc_mode>(UC_MODE_THUMB | UC_MODE_MCLASS), &uc_) != UC_ERR_OK) {
    error_ = "Unicorn: cannot open an ARM M-class engine";
    stopped_ = true;
    return;
  }
  uc_ctl_set_cpu_model(uc_, UC_CPU_ARM_CORTEX_M4);
  map_memory();
  reset();
}

Stm32Machine::~Stm32Machine() {
  if (uc_ != nullptr) uc_close(uc_);
}

void Stm32Machine::map_memory() {
  // The emulated ROM: the DfuSe bootloader's vector table (its stack, its entry) and two
  // instructions the hooks catch; the 96-bit unique ID and the flash size (RM0383 24.1, 24.2).
  auto& rom = mem_->sysmem;
  auto put32 = [&](uint32_t offset, uint32_t v) { std::memcpy(&rom[offset], &v, 4); };
  put32(0, 0x20003000u);
  put32(4, kBootloaderEntry | 1u);
  rom[0x100] = 0xFE; rom[0x101] = 0xE7;  // b .
  rom[0x200] = 0xFE; rom[0x201] = 0xE7;
  put32(0x7A10, 0x00470038u);
  put32(0x7A14, 0x34395111u);
  put32(0x7A18, 0x36383331u);
  rom[0x7A22] = 0x00; rom[0x7A23] = 0x02;  // 512 KiB
  uc_mem_map_ptr(uc_, kFlashBase, kFlashSize, UC_PROT_READ | UC_PROT_EXEC, flash_.data());
  // BOOT0 low: the main flash also appears at 0 (RM0383 2.4), where VTOR points after reset.
  uc_mem_map_ptr(uc_, 0, kFlashSize, UC_PROT_READ | UC_PROT_EXEC, flash_.data());
  uc_mem_map_ptr(uc_, kSramBase, kSramSize, UC_PROT_ALL, mem_->sram.data());
  uc_mem_map_ptr(uc_, kSysmemBase, kSysmemSize, UC_PROT_READ | UC_PROT_EXEC, rom.data());
  uc_mmio_map(uc_, 0x40000000u, 0x24000u, periph_read_cb, this, periph_write_cb, this);
  uc_mmio_map(uc_, 0x50000000u, OtgFs::kSize, otg_read_cb, this, otg_write_cb, this);
  uc_mmio_map(uc_, 0xE000E000u, 0x1000u, scs_read_cb, this, scs_write_cb, this);
  uc_mmio_map(uc_, 0xE0042000u, 0x1000u, dbg_read_cb, this, dbg_write_cb, this);
  uc_hook_add(uc_, &hooks_[0], UC_HOOK_BLOCK, reinterpret_cast<void*>(block_cb), this, 1, 0);
  uc_hook_add(uc_, &hooks_[1], UC_HOOK_CODE, reinterpret_cast<void*>(trampoline_cb), this, kTrampoline, kTrampoline);
  uc_hook_add(uc_, &hooks_[2], UC_HOOK_CODE, reinterpret_cast<void*>(bootloader_cb), this, kBootloaderEntry, kBootloaderEntry);
  uc_hook_add(uc_, &hooks_[3], UC_HOOK_MEM_WRITE_PROT, reinterpret_cast<void*>(flash_write_cb), this, kFlashBase,
              kFlashBase + kFlashSize - 1);
  uc_hook_add(uc_, &hooks_[4], UC_HOOK_INTR, reinterpret_cast<void*>(intr_cb), this, 1, 0);
}

uint32_t Stm32Machine::reg(int id) const {
  uint32_t v = 0;
  uc_reg_read(uc_, id, &v);
  return v;
}

void Stm32Machine::set_reg(int id, uint32_t value) { uc_reg_write(uc_, id, &value); }

void Stm32Machine::load_flash(std::span<const uint8_t> image) {
  std::fill(flash_.begin(), flash_.end(), 0xFF);
  std::copy_n(image.begin(), std::min<size_t>(image.size(), kFlashSize), flash_.begin());
  block_sizes_.clear();
  hook_wfi();
  reset();
}

// WFI: Unicorn halts the CPU until an interrupt it never gets (the NVIC is modelled here), so
// every WFI in flash is caught before it executes; the core then sleeps in run().
void Stm32Machine::hook_wfi() {
  for (const uint64_t h : wfi_hooks_) uc_hook_del(uc_, h);
  wfi_hooks_.clear();
  for (uint32_t offset = 0; offset + 1 < kFlashSize; offset += 2) {
    if (flash_[offset] != 0x30u || flash_[offset + 1] != 0xBFu) continue;
    const uint64_t address = kFlashBase + offset;
    uint64_t hook = 0;
    if (uc_hook_add(uc_, &hook, UC_HOOK_CODE, reinterpret_cast<void*>(wfi_cb), this, address, address) == UC_ERR_OK) {
      wfi_hooks_.push_back(hook);
    }
  }
}

void Stm32Machine::on_wfi(uint64_t address) {
  // PC is set once Unicorn has stopped (a PC written inside a hook restarts the block).
  wfi_pc_ = static_cast<uint32_t>(address);
  uc_emu_stop(uc_);
}

void Stm32Machine::write_flash(uint32_t offset, std::span<const uint8_t> bytes) {
  std::copy_n(bytes.begin(), std::min<size_t>(bytes.size(), kFlashSize - offset), flash_.begin() + offset);
  block_sizes_.clear();
  uc_ctl_remove_cache(uc_, kFlashBase + offset, kFlashBase + offset + static_cast<uint32_t>(bytes.size()));
  hook_wfi();
}

void Stm32Machine::reset() {
  if (uc_ == nullptr) return;
  ++resets_;
  p_->reset();
  otg_.reset();
  active_.clear();
  nvic_enabled_ = {};
  nvic_pending_ = {};
  nvic_priority_ = {};
  systick_csr_ = systick_rvr_ = systick_cvr_ = 0;
  systick_pending_ = false;
  vtor_ = shpr3_ = cpacr_ = aircr_ = 0;
  dbgmcu_apb1_fz_ = 0;
  sleeping_ = in_bootloader_ = reset_requested_ = false;
  // Boot from flash (BOOT0 low): SP and PC from its first two words.
  uint32_t sp = 0;
  uint32_t pc = 0;
  std::memcpy(&sp, flash_.data(), 4);
  std::memcpy(&pc, flash_.data() + 4, 4);
  for (int r = UC_ARM_REG_R0; r <= UC_ARM_REG_R12; ++r) set_reg(r, 0);
  set_reg(UC_ARM_REG_LR, 0xFFFFFFFFu);
  set_reg(UC_ARM_REG_CONTROL, 0);
  set_reg(UC_ARM_REG_PRIMASK, 0);
  set_reg(UC_ARM_REG_MSP, sp);
  set_reg(UC_ARM_REG_SP, sp);
  set_reg(UC_ARM_REG_XPSR, kXpsrThumb);
  set_reg(UC_ARM_REG_PC, pc | 1u);
}

void Stm32Machine::fail(const std::string& message) {
  if (error_.empty()) error_ = message;
  stopped_ = true;
  uc_emu_stop(uc_);
}

void Stm32Machine::trace(const char* peripheral, const char* name, uint32_t address, bool write, uint32_t value) {
  if (!trace_) return;
  char line[160];
  std::snprintf(line, sizeof line, "%12llu %s %s.%s @0x%08X = 0x%08X", static_cast<unsigned long long>(cycles_),
                write ? "W" : "R", peripheral, name, address, value);
  trace_(line);
}

uint32_t Stm32Machine::instructions_in_block(uint64_t address, uint32_t size) const {
  const uint64_t key = (address << 12) | size;
  if (auto it = block_sizes_.find(key); it != block_sizes_.end()) return it->second;
  std::vector<uint8_t> code(size);
  uc_mem_read(uc_, address, code.data(), size);
  uint32_t n = 0;
  for (uint32_t i = 0; i + 1 < size;) {
    const uint16_t hw = static_cast<uint16_t>(code[i] | (code[i + 1] << 8));
    i += is_wide(hw) ? 4u : 2u;
    ++n;
  }
  block_sizes_.emplace(key, n);
  return n;
}

void Stm32Machine::on_block(uint64_t address, uint32_t size) {
  // A stop requested here takes effect before the block runs: the budget is checked first and
  // the block counted only when it is going to execute.
  if (p_->flash_busy_cycles > 0 && address >= kFlashBase && address < kFlashBase + kFlashSize) {
    // RM0383 3.5: an instruction fetch from flash while an erase or a program is going on stalls
    // the bus until it ends (the image must run that wait from RAM).
    budget_stop_pc_ = static_cast<uint32_t>(address);
    flash_stall_ = true;
    uc_emu_stop(uc_);
    return;
  }
  if (cycles_ >= budget_end_) {
    // Unicorn's PC is stale here when the block was reached by a chained jump: remember it.
    budget_stop_pc_ = static_cast<uint32_t>(address);
    uc_emu_stop(uc_);
    return;
  }
  const uint32_t n = instructions_in_block(address, size);
  instructions_ += n;
  cycles_ += n;
}

void Stm32Machine::on_interrupt(uint32_t intno) {
  char line[120];
  std::snprintf(line, sizeof line, "CPU exception %u at pc 0x%08X (a fault the image took: no fault model)", intno,
                reg(UC_ARM_REG_PC));
  fail(line);
}

void Stm32Machine::on_bootloader_entry() {
  in_bootloader_ = true;
  uc_emu_stop(uc_);
}

bool Stm32Machine::run(uint64_t cycles) {
  const uint64_t end = cycles_ + cycles;
  while (!stopped_ && !in_bootloader_ && cycles_ < end) {
    if (reset_requested_) {
      reset();
      continue;
    }
    take_interrupts();
    if (stopped_) break;
    // Cycles to the next event (UINT64_MAX: none), kept from wrapping.
    const uint64_t to_event = std::min(cycles_to_systick(), p_->cycles_to_event());
    const uint64_t next = to_event >= end - cycles_ ? end : cycles_ + to_event;
    if (sleeping_) {
      cycles_ = std::max(next, cycles_ + 1);
      advance_timers(cycles_);
      continue;
    }
    budget_end_ = std::min(next, cycles_ + kSliceCycles);
    const uint32_t pc = reg(UC_ARM_REG_PC);
    budget_stop_pc_ = wfi_pc_ = 0;
    const uc_err err = uc_emu_start(uc_, pc | 1u, 0xFFFFFFFFu, 0, 0);
    if (budget_stop_pc_ != 0) set_reg(UC_ARM_REG_PC, budget_stop_pc_ | 1u);
    if (flash_stall_) {  // stalled on a fetch: time runs to the next event (the end of BSY at the latest)
      flash_stall_ = false;
      cycles_ = std::max(cycles_, next);
    }
    if (wfi_pc_ != 0) {  // the core sleeps after the WFI until an interrupt is pending
      set_reg(UC_ARM_REG_PC, (wfi_pc_ + 2u) | 1u);
      sleeping_ = true;
    }
    advance_timers(cycles_);
    if (err != UC_ERR_OK && !stopped_) {
      char line[160];
      std::snprintf(line, sizeof line, "CPU stopped at pc 0x%08X: %s", reg(UC_ARM_REG_PC), uc_strerror(err));
      fail(line);
    }
  }
  return !stopped_ && !in_bootloader_;
}

bool Stm32Machine::on_flash_write(uint64_t address, int size, int64_t value) {
  return p_->flash_program(*this, static_cast<uint32_t>(address), size, static_cast<uint32_t>(value));
}

void Stm32Machine::flash_store(uint32_t address, int size, uint32_t value) {
  const uint32_t offset = address - kFlashBase;
  for (int i = 0; i < size; ++i) flash_[offset + static_cast<uint32_t>(i)] &= static_cast<uint8_t>(value >> (8 * i));
  block_sizes_.clear();
}

void Stm32Machine::flash_erase(uint32_t offset, uint32_t size) {
  std::fill_n(flash_.begin() + offset, size, 0xFF);
  block_sizes_.clear();
  uc_ctl_remove_cache(uc_, kFlashBase + offset, kFlashBase + offset + size);
}

uint32_t Stm32Machine::pc() const { return reg(UC_ARM_REG_PC); }

std::vector<uint8_t> Stm32Machine::flash() const { return flash_; }

Stm32Outputs Stm32Machine::outputs() const { return p_->outputs(); }

}  // namespace cathbox::emu
