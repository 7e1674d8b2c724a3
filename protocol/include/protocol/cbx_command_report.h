#ifndef CBX_COMMAND_REPORT_H
#define CBX_COMMAND_REPORT_H
/* OUT command report (host -> box, report ID 0x02, every 1 ms): mode and one local force law
 * per axis, rendered by the firmware at >= 10 kHz until the next command. */
#include "protocol/cbx_protocol.h"
#include "protocol/cbx_state_report.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Command flags. */
enum {
  CBX_CMD_ACK_FAULTS = 1u << 0, /* clear latched faults whose cause is gone */
  CBX_CMD_ALL = 0x01u
};

/* out = clamp(offset - stiffness*(pos - pos0)/1e6 - damping*vel/1e6, out_min, out_max)
 *   insertion: out in mN, pos in um, vel in um/s, stiffness in mN/m, damping in mN*s/m
 *   rotation:  out in uNm, pos in urad, vel in urad/s, stiffness in uNm/rad, damping in uNm*s/rad
 * Positive out pushes toward larger positions (insertion: into the patient); with k, b >= 0 the
 * spring pulls back toward pos0 and the damper opposes the motion (restoring, dissipative). */
typedef struct {
  int32_t offset;    /* F0 (mN) or T0 (uNm) */
  int32_t pos0;      /* x0 (um) or theta0 (urad) */
  int32_t stiffness; /* k >= 0 */
  int32_t damping;   /* b >= 0 */
  int32_t out_min;   /* lower clamp, <= out_max */
  int32_t out_max;   /* upper clamp */
} cbx_force_law;

typedef struct {
  cbx_header header;
  uint8_t mode;  /* cbx_mode */
  uint8_t flags; /* CBX_CMD_* */
  cbx_force_law insertion;
  cbx_force_law rotation;
} cbx_command_report;

cbx_status cbx_command_encode(const cbx_command_report* command, uint8_t out[CBX_REPORT_SIZE]);
cbx_status cbx_command_decode(const uint8_t* in, size_t length, cbx_command_report* command);

/* CBX_OK when the law's fields are in range (k, b >= 0 and out_min <= out_max). */
cbx_status cbx_force_law_check(const cbx_force_law* law);
/* Evaluates the law at a position and velocity (64-bit intermediate, saturating to int32). */
int32_t cbx_force_law_eval(const cbx_force_law* law, int32_t pos, int32_t vel);

#ifdef __cplusplus
}
#endif
#endif
