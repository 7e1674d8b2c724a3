// The STM32F411 peripherals the firmware image touches, from RM0383: RCC, PWR, FLASH
// interface, GPIOA-C, SYSCFG, EXTI, TIM2-5, ADC1 and IWDG, each register with its reset value. A
// register not in the table below is not modelled: an access to it stops the machine naming the
// address and the peripheral. Their behaviour: stm32_peripherals.cpp.
#include "stm32_peripherals.hpp"

#include <cstdio>

namespace cathbox::emu {
namespace {

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

}  // namespace cathbox::emu
