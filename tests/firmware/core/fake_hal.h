#ifndef CBX_FAKE_HAL_H
#define CBX_FAKE_HAL_H
/* A fake board for the core tests: virtual time, settable sensors, recorded outputs, and a
 * fixture that steps the core tick by tick. */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "cbx_vectors.h"
#include "firmware/cbx_core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  uint32_t time_us;
  uint32_t counter[CBX_AXIS_COUNT];
  int16_t current_mA[CBX_AXIS_COUNT];
  int16_t mA_per_permille;        /* nonzero: the current follows the drive */
  bool estop;
  uint16_t supply_mV;
  int16_t drive[CBX_AXIS_COUNT];  /* last actuator_set */
  uint32_t actuator_calls;
  bool led;
  uint32_t kicks;
  uint32_t bootloader_requests;
  uint8_t store[256];
  size_t store_size;
  uint32_t saves;
} cbx_fake_board;

extern cbx_fake_board cbx_fake;

/* Resets the fake board (time 0, nothing pressed, empty store). */
void cbx_fake_reset(void);
/* A board config: both encoders `source`, 16-bit counters, actuators `actuator`. */
cbx_core_config cbx_fake_config(cbx_encoder_source source, cbx_actuator actuator);
/* Advances virtual time by one tick period and runs one control tick. */
void cbx_fake_tick(cbx_core* core);
/* Runs ticks for `us` microseconds. */
void cbx_fake_run_us(cbx_core* core, uint32_t us);
/* Sends a command (encoded with the protocol codec); returns the status of the core. */
cbx_status cbx_fake_command(cbx_core* core, uint8_t mode, uint8_t flags, const cbx_force_law* insertion,
                            const cbx_force_law* rotation);
/* Sets the calibration of the "calibration_identity" golden vector through SET_REPORT. */
void cbx_fake_calibrate(cbx_core* core);
/* A force law that asks for a constant output within +-limit. */
cbx_force_law cbx_fake_constant_law(int32_t out, int32_t limit);
/* The core's state (snapshot). */
cbx_state_report cbx_fake_state(cbx_core* core);
/* The golden vector named `name` (NULL if absent). */
const cbx_vector* cbx_fake_vector(const char* name);

#ifdef __cplusplus
}
#endif
#endif
