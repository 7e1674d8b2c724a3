// The emulated STM32F411's memory-mapped registers as Unicorn hands their accesses over: the
// peripherals (stm32_register_table.cpp, stm32_peripherals.cpp), OTG_FS, and the Cortex-M4's System Control Space (NVIC,
// SysTick, SCB) with DBGMCU.
#include "emu/stm32_machine.hpp"

#include <unicorn/unicorn.h>

#include "stm32_core.hpp"
#include "stm32_peripherals.hpp"

namespace cathbox::emu {

using stm32_core::kIrqCount;

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
