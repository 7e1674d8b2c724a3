/* Entering the STM32 ROM DFU bootloader (USB 0483:df11, DfuSe) on the host's request: detach
 * from USB, leave a magic word in RAM that survives reset, reset, and jump from the very start
 * of the reset handler (peripherals and clocks are then in their reset state, as the ROM
 * bootloader expects). */
#include "board.h"
#include "stm32f411_regs.h"
#include "usb_otgfs.h"

#define BOOTLOADER_MAGIC 0xB00710ADu

__attribute__((section(".noinit"))) static volatile uint32_t bootloader_magic;

void board_enter_bootloader(void) {
  board_delay_us(10000u);   /* let the status stage of the SET_REPORT complete */
  usb_otgfs_detach();
  board_delay_us(50000u);   /* the host sees the disconnect */
  bootloader_magic = BOOTLOADER_MAGIC;
  board_reset();
}

void board_reset(void) {
  __asm volatile("dsb");
  SCB_AIRCR = AIRCR_VECTKEY | AIRCR_SYSRESETREQ;
  __asm volatile("dsb");
  for (;;) {
  }
}

void board_bootloader_check(void) {
  if (bootloader_magic != BOOTLOADER_MAGIC) return;
  bootloader_magic = 0u;
  RCC_APB2ENR |= RCC_APB2ENR_SYSCFG;
  (void)RCC_APB2ENR;
  SYSCFG_MEMRMP = SYSCFG_MEMRMP_SYSTEM;
  const uint32_t sp = CBX_REG(SYSTEM_MEMORY_BASE);
  const uint32_t entry = CBX_REG(SYSTEM_MEMORY_BASE + 4u);
  __asm volatile("msr msp, %0\n bx %1\n" : : "r"(sp), "r"(entry) : "memory");
}
