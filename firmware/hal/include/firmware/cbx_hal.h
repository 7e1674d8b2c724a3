#ifndef CBX_HAL_H
#define CBX_HAL_H
/* The whole port contract: what firmware/core calls on a board (ports/stm32f411) or on a
 * simulated board (cathbox-emu, the tests' fake HAL). Every port implements all of these.
 * The core calls them from cbx_core_control_tick() unless noted; none may block. The port in
 * turn calls the entry points of firmware/cbx_core.h (tick, encoder edges, USB reports). */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The two axes of the box. */
typedef enum { CBX_AXIS_INSERTION = 0, CBX_AXIS_ROTATION = 1, CBX_AXIS_COUNT = 2 } cbx_axis;

uint32_t cbx_hal_time_us(void);                       /* free-running microsecond clock, wraps at 2^32; callable from any context */
uint32_t cbx_hal_encoder_counter(cbx_axis axis);      /* raw hardware quadrature counter (axes configured CBX_ENCODER_COUNTER) */
int16_t cbx_hal_current_mA(cbx_axis axis);            /* latest actuator current sample in mA, signed like the drive */
bool cbx_hal_estop_pressed(void);                     /* true while the normally-closed E-stop loop is open (or broken), and once after it opened briefly */
void cbx_hal_actuator_set(cbx_axis axis, int16_t drive_permille); /* drive -1000..1000: |drive| = PWM duty, sign = direction (brakes get >= 0) */
uint16_t cbx_hal_supply_mV(void);                     /* actuator supply voltage in mV (self-test) */
void cbx_hal_led_set(bool on);                        /* status LED (called from cbx_core_background) */
void cbx_hal_watchdog_kick(void);                     /* reload the independent watchdog (once per control tick) */
void cbx_hal_bootloader_request(void);                /* outputs off now; after the current control transfer: detach USB, start the ROM DFU bootloader */
bool cbx_hal_store_load(void* data, size_t size);     /* read the persisted settings block; false if none (called by cbx_core_init) */
bool cbx_hal_store_save(const void* data, size_t size); /* persist the settings block; may take long (cbx_core_background, outputs off) */

#ifdef __cplusplus
}
#endif
#endif
