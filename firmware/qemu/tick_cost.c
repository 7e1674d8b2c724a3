/* Instructions per control tick of the firmware core on a Cortex-M4, counted by QEMU: run with
 * -icount shift=0 so that virtual time advances by 1 ns per executed instruction, and read it
 * with SysTick. The SysTick rate is calibrated against a loop of known instruction count, so
 * the figure does not depend on the emulated clock. Exits non-zero above the 2000-instruction
 * budget. */
#include <stdio.h>
#include <string.h>

#include "fake_hal.h"

#define SYST_CSR (*(volatile uint32_t*)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t*)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t*)0xE000E018u)
#define TICK_BUDGET 2000u
#define TICKS 20000u

static uint32_t now_counts(void) { return SYST_CVR; } /* counts down */

/* 2 instructions per iteration (subs, bne), plus a few around it. */
static void known_loop(uint32_t iterations) {
  __asm volatile("1: subs %0, %0, #1\n bne 1b\n" : "+r"(iterations) : : "cc");
}

static cbx_core core;

static void send_command(void) {
  cbx_force_law law = {.offset = -200, .pos0 = 100000, .stiffness = 400000, .damping = 2000,
                       .out_min = -4000, .out_max = 4000};
  cbx_force_law twist = {.offset = 0, .pos0 = 0, .stiffness = 5000, .damping = 50,
                         .out_min = -20000, .out_max = 20000};
  (void)cbx_fake_command(&core, CBX_MODE_MOTOR, 0, &law, &twist);
}

int main(void) {
  SYST_RVR = 0x00FFFFFFu;
  SYST_CVR = 0u;
  SYST_CSR = 0x5u; /* enable, processor clock, no interrupt */

  /* Calibration: counts per instruction. */
  const uint32_t loop_insns = 2u * 200000u;
  uint32_t a = now_counts();
  known_loop(200000u);
  uint32_t b = now_counts();
  const uint32_t loop_counts = (a - b) & 0x00FFFFFFu;
  a = now_counts();
  b = now_counts();
  const uint32_t overhead_counts = (a - b) & 0x00FFFFFFu;
  /* instructions = counts * loop_insns / loop_counts */

  cbx_fake_reset();
  const cbx_core_config config = cbx_fake_config(CBX_ENCODER_COUNTER, CBX_ACTUATOR_MOTOR);
  cbx_core_init(&core, &config);
  cbx_fake_calibrate(&core);
  /* Warm-up: the first tick also applies the new calibration (a one-off with 64-bit
   * divisions), reported separately. */
  cbx_fake.time_us += CBX_CORE_TICK_US;
  a = now_counts();
  cbx_core_control_tick(&core);
  b = now_counts();
  const uint32_t settings_insns = (uint32_t)((uint64_t)((a - b) & 0x00FFFFFFu) * loop_insns / loop_counts);

  uint64_t total = 0;
  uint32_t worst = 0;
  uint64_t decode_total = 0;
  uint32_t decodes = 0;
  uint8_t report[CBX_REPORT_SIZE];
  for (uint32_t i = 0; i < TICKS; ++i) {
    if (i % 10u == 0u) {
      a = now_counts();
      send_command();
      b = now_counts();
      decode_total += (a - b) & 0x00FFFFFFu;
      decodes++;
      (void)cbx_core_usb_in_report(&core, report);
    }
    cbx_fake.time_us += CBX_CORE_TICK_US;
    cbx_fake.counter[0] += 3u; /* both axes moving, so velocity windows and laws all run */
    cbx_fake.counter[1] -= 1u;
    a = now_counts();
    cbx_core_control_tick(&core);
    b = now_counts();
    uint32_t c = (a - b) & 0x00FFFFFFu;
    c = c > overhead_counts ? c - overhead_counts : 0u;
    total += c;
    if (c > worst) worst = c;
  }
  cbx_state_report s;
  cbx_core_state(&core, &s);
  const uint32_t mean_insns = (uint32_t)(total * loop_insns / loop_counts / TICKS);
  const uint32_t worst_insns = (uint32_t)((uint64_t)worst * loop_insns / loop_counts);
  const uint32_t command_insns = (uint32_t)(decode_total * loop_insns / loop_counts / decodes);
  printf("control tick on Cortex-M4 (QEMU -icount): mean %lu instructions, worst %lu (%lu ticks, "
         "resolution %lu instructions); status 0x%x force %ld mN\n",
         (unsigned long)mean_insns, (unsigned long)worst_insns, (unsigned long)TICKS,
         (unsigned long)(loop_insns / loop_counts + 1u), s.status, (long)s.insertion_force_mN);
  printf("tick that applies new calibration/limits: %lu instructions\n", (unsigned long)settings_insns);
  printf("command encode + cbx_core_usb_out_report (USB context): mean %lu instructions\n",
         (unsigned long)command_insns);
  if (!(s.status & CBX_STATUS_OUTPUT_ENABLED)) {
    printf("tick cost: the output was not enabled, the measurement is not of the rendering path\n");
    return 2;
  }
  if (mean_insns > TICK_BUDGET || worst_insns > 2u * TICK_BUDGET) {
    printf("tick cost: over the budget of %u instructions per tick\n", TICK_BUDGET);
    return 1;
  }
  return 0;
}
