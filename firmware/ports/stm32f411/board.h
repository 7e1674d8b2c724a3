#ifndef CBX_STM32F411_BOARD_H
#define CBX_STM32F411_BOARD_H
/* The STM32F411 "Black Pill" reference board: pins, clocks and peripheral set-up. The pinout
 * table in firmware/README.md is the same as the definitions here. */
#include <stdbool.h>
#include <stdint.h>

#include "firmware/cbx_core.h"

/* Board build options (defaults: magnetic-particle brakes on both axes). */
#ifndef CBX_BOARD_ACTUATOR
#define CBX_BOARD_ACTUATOR CBX_ACTUATOR_BRAKE
#endif
#define CBX_BOARD_INSERTION_CPR 2400u /* 600-line encoder, x4 */
#define CBX_BOARD_ROTATION_CPR 4096u  /* 1024-line encoder, x4 */
#define CBX_BOARD_NAME "stm32f411-bp"

/* Clocks. */
#define CBX_HCLK_HZ 96000000u
#define CBX_TIMER_CLK_HZ 96000000u  /* APB1 timers (x2 of 48 MHz) and APB2 timers */
#define CBX_PWM_HZ 20000u
#define CBX_PWM_PERIOD (CBX_TIMER_CLK_HZ / CBX_PWM_HZ) /* 4800 counts */

/* Current sense: bidirectional amplifier, zero at 1650 mV, 500 mV per A; supply divider 1:11. */
#define CBX_ADC_VREF_MV 3300u
#define CBX_CURRENT_ZERO_MV 1650
#define CBX_CURRENT_MV_PER_A 500
#define CBX_SUPPLY_DIVIDER 11u

/* Sets up the clock tree: 25 MHz HSE -> PLL -> 96 MHz core, 48 MHz USB (HSI fallback). Returns
 * false when the HSE did not start (USB timing is then out of spec). */
bool board_clock_init(void);
/* GPIO, encoder timers, PWM, ADC, E-stop interrupt, microsecond timer, watchdog. */
void board_init(void);
/* Once per control tick, before the core: latch the last ADC results and start the next. */
void board_adc_cycle(void);
/* The serial number from the chip's unique ID ("CBX-" + 12 hex digits). */
void board_serial(char out[CBX_TEXT_FIELD + 1]);
/* The core's view of this board: serial, name, encoders and actuators, the image's version and
 * build (those of image_info.c), and the board faults found at start-up (`hse_started` false:
 * CBX_BOARD_FAULT_HSE). */
void board_core_config(cbx_core_config* config, bool hse_started);
/* True once cbx_hal_bootloader_request() was called. */
bool board_bootloader_requested(void);
/* Reset into the ROM DFU bootloader (never returns). */
void board_enter_bootloader(void) __attribute__((noreturn));
/* System reset (never returns). */
void board_reset(void) __attribute__((noreturn));
/* Early in the reset handler: jumps into the ROM bootloader if the last reset asked for it. */
void board_bootloader_check(void);
/* PWM duty 0 and the driver disabled, at once (E-stop interrupt, bootloader, fault handlers). */
void board_outputs_off(void);
/* At boot, before USB starts: erases the settings store's sector (1-2 s) when fewer than half
 * its slots are blank, keeping the newest block (flash_store.c). */
void flash_store_prepare(void);
/* Busy wait on the microsecond timer. */
void board_delay_us(uint32_t us);

#endif
