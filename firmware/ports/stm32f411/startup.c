/* Reset handler and vector table of the STM32F411 (16 system exceptions + 86 interrupts).
 * Reset: jump into the ROM bootloader if asked to, copy .data (and the RAM functions), clear
 * .bss, enable the FPU, then main(). */
#include <stdint.h>

#include "board.h"
#include "stm32f411_regs.h"

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;
int main(void);
void Reset_Handler(void);
void default_handler(void);
void HardFault_Handler(void);
void SysTick_Handler(void);
void EXTI9_5_IRQHandler(void);
void OTG_FS_IRQHandler(void);

typedef struct vector_table vector_table;
static const vector_table vectors;

void Reset_Handler(void) {
  board_bootloader_check();
  /* Started by a jump, not a reset (the ROM DFU bootloader's "leave" after dfu-util's
   * :leave): the PLL, USB core, interrupts and memory remap are as the ROM left them. One
   * system reset gives a clean start; every reset leaves the PLL off. */
  if (RCC_CR & RCC_CR_PLLON) board_reset();
  SCB_VTOR = (uint32_t)&vectors; /* not address 0: that may still alias the system memory */
  for (uint32_t *src = &_sidata, *dst = &_sdata; dst < &_edata;) *dst++ = *src++;
  for (uint32_t* dst = &_sbss; dst < &_ebss;) *dst++ = 0u;
  SCB_CPACR |= 0xFu << 20; /* CP10, CP11 full access */
  __asm volatile("dsb\n isb");
  (void)main();
  for (;;) {
  }
}

/* Unexpected interrupts and faults: outputs off at once (the PWM timer would otherwise keep
 * the last duty until the reset), then stop; the independent watchdog resets the chip. */
void default_handler(void) {
  board_outputs_off();
  for (;;) {
  }
}

void HardFault_Handler(void) {
  board_outputs_off();
  for (;;) {
  }
}

struct vector_table {
  void* initial_sp;
  void (*handlers[15 + IRQ_COUNT])(void);
};

__attribute__((section(".isr_vector"), used)) static const vector_table vectors = {
    &_estack,
    {
    Reset_Handler, default_handler, HardFault_Handler, default_handler, /* Reset NMI HardFault MemManage */
    default_handler, default_handler, 0, 0, 0, 0,                       /* BusFault UsageFault reserved */
    default_handler, default_handler, 0, default_handler,               /* SVCall DebugMon reserved PendSV */
    SysTick_Handler,
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 0.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 4.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 8.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 12.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 16.. */
    default_handler, default_handler, default_handler, EXTI9_5_IRQHandler,  /* IRQ 20.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 24.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 28.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 32.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 36.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 40.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 44.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 48.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 52.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 56.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 60.. */
    default_handler, default_handler, default_handler, OTG_FS_IRQHandler,  /* IRQ 64.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 68.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 72.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 76.. */
    default_handler, default_handler, default_handler, default_handler,  /* IRQ 80.. */
    default_handler, default_handler,  /* IRQ 84.. */
    }};
