#pragma once
// The Cortex-M4 facts the emulated STM32F411's core files share (stm32_machine.cpp,
// stm32_exceptions.cpp, stm32_register_access.cpp). Private to hw-sim.
#include <cstdint>

#include "emu/stm32_machine.hpp"

namespace cathbox::emu::stm32_core {

inline constexpr uint32_t kTrampoline = Stm32Machine::kSysmemBase + 0x200u;  // exception return (EXC_RETURN stand-in)
inline constexpr uint32_t kSysTickException = 15u;
inline constexpr uint32_t kIrqCount = 86u;
inline constexpr uint32_t kXpsrThumb = 1u << 24;

}  // namespace cathbox::emu::stm32_core
