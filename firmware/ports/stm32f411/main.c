/* STM32F411 firmware entry: clocks, board, the core, USB, the 10 kHz control tick (SysTick,
 * highest priority) and the main loop (settings storage, LED, bootloader entry). The settings sector is
 * erased, when it must be, before USB starts (flash_store.c). */
#include "board.h"
#include "firmware/cbx_core.h"
#include "stm32f411_regs.h"
#include "usb_device.h"

static cbx_core core;

void SysTick_Handler(void);
void SysTick_Handler(void) {
  board_adc_cycle();
  cbx_core_control_tick(&core);
}

int main(void) {
  /* No crystal: the box runs on HSI, USB timing out of spec; every state report says so
   * (board fault HSE) and `cathbox info` / `monitor` print it. */
  const bool hse_started = board_clock_init();
  board_init();
  flash_store_prepare(); /* any erase of the settings sector happens here, before USB */

  cbx_core_config config;
  board_core_config(&config, hse_started);
  cbx_core_init(&core, &config);

  /* Control tick: SysTick at 10 kHz, priority 0 (above USB). */
  SCB_SHPR3 = (SCB_SHPR3 & 0x00FFFFFFu) | (0x00u << 24);
  SYST_RVR = CBX_HCLK_HZ / CBX_CORE_TICK_HZ - 1u;
  SYST_CVR = 0u;
  SYST_CSR = 0x7u; /* processor clock, interrupt, enable */

  usb_device_start(&core);

  for (;;) {
    cbx_core_background(&core);
    if (board_bootloader_requested()) board_enter_bootloader();
    __asm volatile("wfi");
  }
}
