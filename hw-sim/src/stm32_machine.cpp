// The Cortex-M4 side of the emulated STM32F411: Unicorn, memory map, NVIC, SysTick, SCB,
// exception entry and return, instruction counting. The peripherals are in
// stm32_peripherals.cpp.
#include "emu/stm32_machine.hpp"

#include <unicorn/unicorn.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "stm32_peripherals.hpp"

namespace cathbox::emu {
namespace {

constexpr uint32_t kTrampoline = Stm32Machine::kSysmemBase + 0x200u;  // exception return (EXC_RETURN stand-in)
constexpr uint32_t kSysmemSize = 0x8000u;
constexpr uint32_t kSysTickException = 15u;
constexpr uint32_t kIrqCount = 86u;
constexpr uint32_t kXpsrThumb = 1u << 24;
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

int Stm32Machine::exception_priority(uint32_t exception) const {
  if (exception == kSysTickException) return static_cast<int>(shpr3_ >> 24);
  return nvic_priority_[exception - 16u];
}

int Stm32Machine::pending_exception(int& priority) const {
  int best = -1;
  priority = 256;
  auto consider = [&](uint32_t exception) {
    const int p = exception_priority(exception);
    if (p < priority) {
      priority = p;
      best = static_cast<int>(exception);
    }
  };
  if (systick_pending_) consider(kSysTickException);
  for (uint32_t irq = 0; irq < kIrqCount; ++irq) {
    const uint32_t bit = 1u << (irq % 32u);
    if ((nvic_pending_[irq / 32u] & bit) && (nvic_enabled_[irq / 32u] & bit)) consider(16u + irq);
  }
  return best;
}

void Stm32Machine::take_interrupts() {
  p_->update_irqs(*this);
  if (otg_.irq()) nvic_pending_[2] |= 1u << (67u - 64u);
  int priority = 0;
  const int exception = pending_exception(priority);
  if (exception < 0) return;
  sleeping_ = false;  // WFI wakes on a pending interrupt
  if (reg(UC_ARM_REG_PRIMASK) & 1u) return;
  // Priority: the STM32F4 implements 4 bits (the top of each byte); equal priority does not preempt.
  if (!active_.empty() && (priority & 0xF0) >= (active_.back().priority & 0xF0)) return;
  enter(static_cast<uint32_t>(exception), priority);
}

void Stm32Machine::enter(uint32_t exception, int priority) {
  if (exception == kSysTickException) {
    systick_pending_ = false;
  } else {
    nvic_pending_[(exception - 16u) / 32u] &= ~(1u << ((exception - 16u) % 32u));
  }
  Frame f{};
  f.exception = exception;
  f.priority = priority;
  f.start_instructions = instructions_;
  for (int i = 0; i < 16; ++i) uc_reg_read(uc_, UC_ARM_REG_D0 + i, &f.fp[static_cast<size_t>(i)]);
  f.fpscr = reg(UC_ARM_REG_FPSCR);
  // The basic frame (R0-R3, R12, LR, return address, xPSR), 8-byte aligned (CCR.STKALIGN).
  uint32_t sp = reg(UC_ARM_REG_SP);
  uint32_t xpsr = reg(UC_ARM_REG_XPSR);
  if (sp & 4u) {
    sp -= 4u;
    xpsr |= 1u << 9;
  }
  sp -= 32u;
  const uint32_t frame[8] = {reg(UC_ARM_REG_R0), reg(UC_ARM_REG_R1), reg(UC_ARM_REG_R2), reg(UC_ARM_REG_R3),
                             reg(UC_ARM_REG_R12), reg(UC_ARM_REG_LR), reg(UC_ARM_REG_PC) | 1u, xpsr};
  if (uc_mem_write(uc_, sp, frame, sizeof frame) != UC_ERR_OK) {
    fail("exception entry: stack pointer 0x" + std::to_string(sp) + " outside SRAM");
    return;
  }
  uint32_t handler = 0;
  if (uc_mem_read(uc_, vtor_ + 4u * exception, &handler, 4) != UC_ERR_OK || (handler & ~1u) == 0u) {
    fail("exception " + std::to_string(exception) + ": no handler in the vector table at VTOR");
    return;
  }
  active_.push_back(f);
  set_reg(UC_ARM_REG_SP, sp);
  set_reg(UC_ARM_REG_LR, kTrampoline | 1u);
  set_reg(UC_ARM_REG_PC, handler | 1u);
}

void Stm32Machine::on_return_trampoline() {
  if (active_.empty()) {
    fail("exception return with no exception active");
    return;
  }
  const Frame f = active_.back();
  active_.pop_back();
  if (f.exception == kSysTickException) {
    tick_last_ = instructions_ - f.start_instructions;
    tick_max_ = std::max(tick_max_, tick_last_);
    ++ticks_;
  }
  uint32_t sp = reg(UC_ARM_REG_SP);
  uint32_t frame[8];
  uc_mem_read(uc_, sp, frame, sizeof frame);
  sp += 32u + ((frame[7] & (1u << 9)) ? 4u : 0u);
  set_reg(UC_ARM_REG_R0, frame[0]);
  set_reg(UC_ARM_REG_R1, frame[1]);
  set_reg(UC_ARM_REG_R2, frame[2]);
  set_reg(UC_ARM_REG_R3, frame[3]);
  set_reg(UC_ARM_REG_R12, frame[4]);
  set_reg(UC_ARM_REG_LR, frame[5]);
  set_reg(UC_ARM_REG_XPSR, (frame[6] & 1u ? kXpsrThumb : 0u) | (frame[7] & 0xF80F0000u) | kXpsrThumb);
  set_reg(UC_ARM_REG_SP, sp);
  for (int i = 0; i < 16; ++i) uc_reg_write(uc_, UC_ARM_REG_D0 + i, &f.fp[static_cast<size_t>(i)]);
  set_reg(UC_ARM_REG_FPSCR, f.fpscr);
  set_reg(UC_ARM_REG_PC, frame[6] | 1u);
  uc_emu_stop(uc_);  // tail-chaining: whatever is pending is taken before the thread resumes
}

void Stm32Machine::advance_timers(uint64_t now) {
  const uint64_t elapsed = now - timer_cycles_;
  timer_cycles_ = now;
  if ((systick_csr_ & 1u) && systick_rvr_ > 0) {
    const uint64_t period = static_cast<uint64_t>(systick_rvr_) + 1u;
    uint64_t left = elapsed;
    while (left > 0) {
      const uint64_t to_wrap = systick_cvr_ == 0 ? period : systick_cvr_;
      if (left < to_wrap) {
        systick_cvr_ = static_cast<uint32_t>(to_wrap - left);
        break;
      }
      left -= to_wrap;
      systick_cvr_ = 0;
      if (systick_csr_ & 2u) systick_pending_ = true;
      systick_csr_ |= 1u << 16;
      if (left == 0) systick_cvr_ = systick_rvr_ + 1u;
    }
  }
  p_->advance(*this, elapsed);
}

uint64_t Stm32Machine::cycles_to_systick() const {
  if (!(systick_csr_ & 1u) || systick_rvr_ == 0) return UINT64_MAX;
  return systick_cvr_ == 0 ? systick_rvr_ + 1u : systick_cvr_;
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

uint64_t Stm32Machine::periph_read(uint32_t address, unsigned size) {
  uint32_t v = 0;
  if (!p_->read(*this, address, size, v)) fail(Peripherals::unmodelled(address, false));
  return v;
}

void Stm32Machine::periph_write(uint32_t address, unsigned size, uint32_t value) {
  if (!p_->write(*this, address, size, value)) fail(Peripherals::unmodelled(address, true));
}

uint64_t Stm32Machine::otg_read(uint32_t offset, unsigned) {
  uint32_t v = 0;
  if (!otg_.read(offset, v)) fail(Peripherals::unmodelled(0x50000000u + offset, false));
  trace("OTG_FS", OtgFs::register_name(offset), 0x50000000u + offset, false, v);
  return v;
}

void Stm32Machine::otg_write(uint32_t offset, unsigned, uint32_t value) {
  if (!otg_.write(offset, value)) fail(Peripherals::unmodelled(0x50000000u + offset, true));
  trace("OTG_FS", OtgFs::register_name(offset), 0x50000000u + offset, true, value);
}

uint64_t Stm32Machine::scs_read(uint32_t address, unsigned size) {
  uint32_t v = 0;
  const char* name = "?";
  if (address == 0xE0042008u) {
    v = dbgmcu_apb1_fz_; name = "DBGMCU_APB1_FZ";
  } else if (address >= 0xE000E400u && address < 0xE000E400u + kIrqCount) {
    v = nvic_priority_[address - 0xE000E400u]; name = "NVIC_IPR";
    if (size == 4) for (uint32_t i = 1; i < 4; ++i) v |= static_cast<uint32_t>(nvic_priority_[address - 0xE000E400u + i]) << (8 * i);
  } else if (address >= 0xE000E100u && address < 0xE000E10Cu) {
    v = nvic_enabled_[(address - 0xE000E100u) / 4]; name = "NVIC_ISER";
  } else if (address >= 0xE000E180u && address < 0xE000E18Cu) {
    v = nvic_enabled_[(address - 0xE000E180u) / 4]; name = "NVIC_ICER";
  } else if (address >= 0xE000E200u && address < 0xE000E20Cu) {
    v = nvic_pending_[(address - 0xE000E200u) / 4]; name = "NVIC_ISPR";
  } else {
    switch (address) {
      case 0xE000E010u: v = systick_csr_; systick_csr_ &= ~(1u << 16); name = "SYST_CSR"; break;
      case 0xE000E014u: v = systick_rvr_; name = "SYST_RVR"; break;
      case 0xE000E018u: v = systick_cvr_; name = "SYST_CVR"; break;
      case 0xE000ED00u: v = 0x410FC241u; name = "SCB_CPUID"; break;
      case 0xE000ED08u: v = vtor_; name = "SCB_VTOR"; break;
      case 0xE000ED0Cu: v = 0xFA050000u | (aircr_ & 0x700u); name = "SCB_AIRCR"; break;
      case 0xE000ED20u: v = shpr3_; name = "SCB_SHPR3"; break;
      case 0xE000ED88u: v = cpacr_; name = "SCB_CPACR"; break;
      default: fail(Peripherals::unmodelled(address, false)); return 0;
    }
  }
  trace("SCS", name, address, false, v);
  return v;
}

void Stm32Machine::scs_write(uint32_t address, unsigned size, uint32_t v) {
  const char* name = "?";
  if (address == 0xE0042008u) {
    dbgmcu_apb1_fz_ = v; name = "DBGMCU_APB1_FZ";
  } else if (address >= 0xE000E400u && address < 0xE000E400u + kIrqCount) {
    name = "NVIC_IPR";
    for (uint32_t i = 0; i < size && address - 0xE000E400u + i < kIrqCount; ++i)
      nvic_priority_[address - 0xE000E400u + i] = static_cast<uint8_t>((v >> (8 * i)) & 0xF0u);
  } else if (address >= 0xE000E100u && address < 0xE000E10Cu) {
    nvic_enabled_[(address - 0xE000E100u) / 4] |= v; name = "NVIC_ISER";
  } else if (address >= 0xE000E180u && address < 0xE000E18Cu) {
    nvic_enabled_[(address - 0xE000E180u) / 4] &= ~v; name = "NVIC_ICER";
  } else if (address >= 0xE000E200u && address < 0xE000E20Cu) {
    nvic_pending_[(address - 0xE000E200u) / 4] |= v; name = "NVIC_ISPR";
  } else if (address >= 0xE000E280u && address < 0xE000E28Cu) {
    nvic_pending_[(address - 0xE000E280u) / 4] &= ~v; name = "NVIC_ICPR";
  } else {
    switch (address) {
      case 0xE000E010u: systick_csr_ = (systick_csr_ & (1u << 16)) | (v & 7u); name = "SYST_CSR"; break;
      case 0xE000E014u: systick_rvr_ = v & 0xFFFFFFu; name = "SYST_RVR"; break;
      case 0xE000E018u: systick_cvr_ = 0; systick_csr_ &= ~(1u << 16); name = "SYST_CVR"; break;
      case 0xE000ED08u: vtor_ = v & 0xFFFFFE00u; name = "SCB_VTOR"; break;
      case 0xE000ED0Cu:
        name = "SCB_AIRCR";
        if ((v >> 16) == 0x05FAu) {
          aircr_ = v & 0x700u;
          if (v & (1u << 2)) {  // SYSRESETREQ
            reset_requested_ = true;
            uc_emu_stop(uc_);
          }
        }
        break;
      case 0xE000ED20u: shpr3_ = v & 0xF0F00000u; name = "SCB_SHPR3"; break;
      case 0xE000ED88u: cpacr_ = v & (0xFu << 20); name = "SCB_CPACR"; break;
      default: fail(Peripherals::unmodelled(address, true)); return;
    }
  }
  trace("SCS", name, address, true, v);
}

}  // namespace cathbox::emu
