// The emulated Cortex-M4's exceptions: priorities, the pending one the NVIC and SysTick offer,
// exception entry (the stacked frame, the vector) and return through the trampoline, and the
// SysTick and peripheral timers advanced by the cycles run.
#include "emu/stm32_machine.hpp"

#include <unicorn/unicorn.h>

#include "stm32_core.hpp"
#include "stm32_peripherals.hpp"

namespace cathbox::emu {

using stm32_core::kIrqCount;
using stm32_core::kSysTickException;
using stm32_core::kTrampoline;
using stm32_core::kXpsrThumb;

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

}  // namespace cathbox::emu
