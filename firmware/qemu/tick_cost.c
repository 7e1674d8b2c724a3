/* Instructions per 10 kHz control tick of the firmware on a Cortex-M4, counted by QEMU
 * (mps2-an386). The tick is measured as the STM32F411 image runs it in its SysTick handler:
 * board_adc_cycle() then cbx_core_control_tick(), on the port's own HAL (ports/stm32f411/board.c
 * and flash_store.c) built with its register blocks in RAM (CBX_PERIPH_BASE and CBX_FLASH_BASE
 * are constants, see CMakeLists.txt, so the instructions are the image's), across operating
 * points: brake and motor actuators, counter and raw-edge encoders, a latched fault, the
 * watchdog ramp and the self-test drive. Also measured: the tick that applies new calibration
 * or limits while rendering, and the USB-context work of each 1 ms frame (command decode, state
 * report), plus one encoder edge (the edge interrupt of an edge-source port).
 *
 * Counting: `-icount shift=6` makes virtual time advance 64 ns per executed instruction, read
 * through SysTick (25 MHz on this board: 1.6 counts per instruction). Counts per instruction
 * are calibrated against a loop of known instruction count, so the figures do not depend on the
 * shift or the clock. Exit 0 when every worst case is within TICK_BUDGET, 1 when one is over
 * it, 2 when an operating point did not reach the state it is meant to measure. */
#include <stdio.h>
#include <string.h>

#include "board.h"
#include "firmware/cbx_core.h"
#include "protocol/cbx_command_report.h"
#include "protocol/cbx_feature_reports.h"
#include "stm32f411_regs.h"

#define TICK_BUDGET 2000u
#define TICKS_PER_POINT 4000u
#define SETTINGS_CHANGES 64u
#define QEMU_SYST_CSR (*(volatile uint32_t*)0xE000E010u) /* QEMU's own SysTick, not remapped */
#define QEMU_SYST_RVR (*(volatile uint32_t*)0xE000E014u)
#define QEMU_SYST_CVR (*(volatile uint32_t*)0xE000E018u)

/* ---- Counting ---- */

static uint32_t loop_insns, loop_counts, overhead_counts;

/* 2 instructions per iteration (subs, bne). */
static void known_loop(uint32_t iterations) {
  __asm volatile("1: subs %0, %0, #1\n bne 1b\n" : "+r"(iterations) : : "cc");
}

static void calibrate_counter(void) {
  QEMU_SYST_RVR = 0x00FFFFFFu;
  QEMU_SYST_CVR = 0u;
  QEMU_SYST_CSR = 0x5u; /* enable, processor clock, no interrupt */
  loop_insns = 2u * 100000u;
  uint32_t a = QEMU_SYST_CVR;
  known_loop(100000u);
  uint32_t b = QEMU_SYST_CVR;
  loop_counts = (a - b) & 0x00FFFFFFu;
  a = QEMU_SYST_CVR;
  b = QEMU_SYST_CVR;
  overhead_counts = (a - b) & 0x00FFFFFFu;
}

static uint32_t counts_to_insns(uint64_t counts) { return (uint32_t)((counts * loop_insns + loop_counts / 2u) / loop_counts); }

typedef struct {
  const char* name;
  uint32_t n;
  uint64_t total_counts;
  uint32_t worst_counts;
} cost;

#define MEASURE(c, stmt)                                                  \
  do {                                                                    \
    const uint32_t cbx_a_ = QEMU_SYST_CVR;                                \
    stmt;                                                                 \
    const uint32_t cbx_b_ = QEMU_SYST_CVR;                                \
    uint32_t cbx_d_ = (cbx_a_ - cbx_b_) & 0x00FFFFFFu;                    \
    cbx_d_ = cbx_d_ > overhead_counts ? cbx_d_ - overhead_counts : 0u;    \
    (c)->n++;                                                             \
    (c)->total_counts += cbx_d_;                                          \
    if (cbx_d_ > (c)->worst_counts) (c)->worst_counts = cbx_d_;           \
  } while (0)

static int over_budget;

static void report(const cost* c, bool gated) {
  if (c->n == 0u) return;
  const uint32_t mean = counts_to_insns(c->total_counts / c->n);
  const uint32_t worst = counts_to_insns(c->worst_counts);
  const bool over = gated && worst > TICK_BUDGET;
  printf("  %-52s mean %5lu  worst %5lu  (%lu runs)%s\n", c->name, (unsigned long)mean, (unsigned long)worst,
         (unsigned long)c->n, over ? "  OVER BUDGET" : "");
  if (over) over_budget = 1;
}

/* ---- The board around the port's HAL: what the hardware does between two ticks ---- */

static cbx_core core;
static uint8_t edge_phase[CBX_AXIS_COUNT];
static const uint8_t gray[4] = {0u, 1u, 3u, 2u};

static uint32_t adc_raw_for_mA(int32_t mA) {
  const int32_t mv = CBX_CURRENT_ZERO_MV + mA * CBX_CURRENT_MV_PER_A / 1000;
  return (uint32_t)(mv * 4095 / (int32_t)CBX_ADC_VREF_MV);
}

static void board_reset_registers(void) {
  memset((void*)CBX_PERIPH_BASE, 0, 0x24000u);
  memset((void*)(CBX_FLASH_BASE + 0x20000u), 0xFF, 0x200u); /* an erased settings sector */
  ADC1_JDR(1) = ADC1_JDR(2) = adc_raw_for_mA(0);
  ADC1_JDR(3) = 12000u / CBX_SUPPLY_DIVIDER * 4095u / CBX_ADC_VREF_MV;
  memset(edge_phase, 0, sizeof edge_phase);
}

/* One tick period of the hardware: the 1 MHz time base, the encoders (timer counters, or A/B
 * edges fed to the core as an edge interrupt would), the ADC scan the last tick started. */
static void board_period(const cbx_core_config* config, int32_t insertion_counts, int32_t rotation_counts,
                         cost* edge_cost) {
  TIM5->CNT += CBX_CORE_TICK_US;
  const int32_t moves[CBX_AXIS_COUNT] = {insertion_counts, rotation_counts};
  for (int a = 0; a < CBX_AXIS_COUNT; ++a) {
    if (config->axis[a].encoder_source == CBX_ENCODER_COUNTER) {
      cbx_tim_regs* tim = a == CBX_AXIS_INSERTION ? TIM2 : TIM3;
      const uint32_t mask = config->axis[a].counter_bits >= 32u ? 0xFFFFFFFFu : (1u << config->axis[a].counter_bits) - 1u;
      tim->CNT = (tim->CNT + (uint32_t)moves[a]) & mask;
      continue;
    }
    const int32_t n = moves[a] < 0 ? -moves[a] : moves[a];
    for (int32_t i = 0; i < n; ++i) {
      edge_phase[a] = (uint8_t)((edge_phase[a] + (moves[a] > 0 ? 1u : 3u)) & 3u);
      MEASURE(edge_cost, cbx_core_encoder_edge(&core, (cbx_axis)a, gray[edge_phase[a]]));
    }
  }
  ADC1_SR |= ADC_SR_JEOC;
  const int32_t ma_per_permille = 1; /* 1000 mA at full drive */
  ADC1_JDR(1) = adc_raw_for_mA(ma_per_permille * TIM4->CCR1 * 1000 / (int32_t)CBX_PWM_PERIOD);
  ADC1_JDR(2) = adc_raw_for_mA(ma_per_permille * TIM4->CCR2 * 1000 / (int32_t)CBX_PWM_PERIOD);
}

static void systick(void) {
  board_adc_cycle();
  cbx_core_control_tick(&core);
}

/* ---- The host's side, in the USB context ---- */

static uint16_t host_seq;

static void encode_feature(uint8_t id, const void* value, uint8_t out[CBX_REPORT_SIZE]) {
  cbx_header h = {CBX_PROTOCOL_VERSION, ++host_seq, TIM5->CNT};
  cbx_status st = CBX_ERR_REPORT_ID;
  switch (id) {
    case CBX_ID_CALIBRATION: {
      cbx_calibration c = *(const cbx_calibration*)value;
      c.header = h;
      st = cbx_calibration_encode(&c, out);
      break;
    }
    case CBX_ID_LIMITS: {
      cbx_limits l = *(const cbx_limits*)value;
      l.header = h;
      st = cbx_limits_encode(&l, out);
      break;
    }
    case CBX_ID_SELFTEST: {
      cbx_selftest t;
      memset(&t, 0, sizeof t);
      t.header = h;
      t.state = CBX_SELFTEST_RUNNING;
      st = cbx_selftest_encode(&t, out);
      break;
    }
    default:
      break;
  }
  if (st != CBX_OK) printf("tick cost: cannot encode feature 0x%02x (%d)\n", id, (int)st);
}

static cbx_calibration calibration(uint32_t insertion_counts_per_m) {
  cbx_calibration c;
  memset(&c, 0, sizeof c);
  c.insertion_counts_per_m = insertion_counts_per_m;
  c.rotation_counts_per_rev = 4096u;
  c.insertion_full_scale_mN = 5000u;
  c.rotation_full_scale_uNm = 50000u;
  const uint16_t in[CBX_CURVE_POINTS] = {100u, 300u, 600u, 1000u};
  const uint16_t out[CBX_CURVE_POINTS] = {180u, 420u, 700u, 1000u}; /* a brake's curve */
  for (unsigned i = 0; i < CBX_CURVE_POINTS; ++i) {
    c.insertion_curve[i] = (cbx_curve_point){in[i], out[i]};
    c.rotation_curve[i] = (cbx_curve_point){in[i], out[i]};
  }
  return c;
}

static cbx_limits limits(uint32_t max_force_mN) {
  cbx_settings s;
  cbx_core_default_settings(&s);
  s.limits.max_force_mN = max_force_mN;
  return s.limits;
}

/* A command as the host streams it: a wall with damping on insertion, a torsion spring on
 * rotation, both inside their clamps, pos0 moving so that the laws are evaluated fresh. */
static void encode_command(uint8_t mode, uint8_t flags, uint32_t frame, uint8_t out[CBX_REPORT_SIZE]) {
  cbx_command_report c;
  memset(&c, 0, sizeof c);
  c.header = (cbx_header){CBX_PROTOCOL_VERSION, ++host_seq, TIM5->CNT};
  c.mode = mode;
  c.flags = flags;
  c.insertion = (cbx_force_law){-200, (int32_t)(1000u * (frame % 97u)), 400000, 2000, -4000, 4000};
  c.rotation = (cbx_force_law){0, (int32_t)(3000u * (frame % 89u)), 5000, 50, -20000, 20000};
  if (cbx_command_encode(&c, out) != CBX_OK) printf("tick cost: cannot encode the command\n");
}

static cost decode_cost = {"USB: command decode (cbx_core_usb_out_report)", 0, 0, 0};
static cost state_cost = {"USB: state report (cbx_core_usb_in_report)", 0, 0, 0};
static cost feature_cost = {"USB: calibration / limits SET_REPORT", 0, 0, 0};
static cost edge_cost = {"edge interrupt: one A/B sample (cbx_core_encoder_edge)", 0, 0, 0};

static void usb_frame(uint8_t mode, uint8_t flags, uint32_t frame) {
  uint8_t report[CBX_REPORT_SIZE];
  encode_command(mode, flags, frame, report);
  cbx_status st = CBX_OK;
  MEASURE(&decode_cost, st = cbx_core_usb_out_report(&core, report, sizeof report));
  if (st != CBX_OK) printf("tick cost: the core refused a command (%d)\n", (int)st);
  bool sent = false;
  MEASURE(&state_cost, sent = cbx_core_usb_in_report(&core, report));
  (void)sent;
}

static void usb_feature(uint8_t id, const void* value) {
  uint8_t report[CBX_REPORT_SIZE];
  encode_feature(id, value, report);
  cbx_status st = CBX_OK;
  MEASURE(&feature_cost, st = cbx_core_usb_feature_set(&core, report, sizeof report));
  if (st != CBX_OK) printf("tick cost: the core refused feature 0x%02x (%d)\n", id, (int)st);
}

/* ---- Operating points ---- */

static cbx_core_config board_config(uint8_t actuator, uint8_t source) {
  cbx_core_config c;
  memset(&c, 0, sizeof c);
  strcpy(c.serial, "CBX-QEMU");
  strcpy(c.board, CBX_BOARD_NAME);
  c.axis[CBX_AXIS_INSERTION] = (cbx_axis_config){source, 32u, actuator, CBX_BOARD_INSERTION_CPR};
  c.axis[CBX_AXIS_ROTATION] = (cbx_axis_config){source, 16u, actuator, CBX_BOARD_ROTATION_CPR};
  return c;
}

typedef enum { STIM_RENDER, STIM_ESTOP, STIM_WATCHDOG, STIM_SELFTEST } stimulus;

typedef struct {
  const char* name;
  uint8_t actuator;
  uint8_t source;
  stimulus stim;
} operating_point;

static bool started(const cbx_core_config* config) {
  board_reset_registers();
  cbx_core_init(&core, config);
  const cbx_calibration c = calibration(108650u);
  usb_feature(CBX_ID_CALIBRATION, &c);
  return true;
}

/* Runs one operating point; returns false when it did not reach the state it measures. */
static bool run_point(const operating_point* p) {
  const cbx_core_config config = board_config(p->actuator, p->source);
  (void)started(&config);
  cost tick = {p->name, 0, 0, 0};
  bool reached = false;
  const uint8_t mode = p->actuator == CBX_ACTUATOR_MOTOR ? CBX_MODE_MOTOR : CBX_MODE_BRAKE;
  if (p->stim == STIM_SELFTEST) {
    usb_frame(CBX_MODE_OFF, 0u, 0u);
    for (int i = 0; i < 10; ++i) {
      board_period(&config, 0, 0, &edge_cost);
      systick();
    }
    usb_feature(CBX_ID_SELFTEST, NULL);
  }
  for (uint32_t i = 0; i < TICKS_PER_POINT; ++i) {
    const uint32_t frame = i / 10u;
    if (i % 10u == 0u) {
      const bool streaming = p->stim != STIM_SELFTEST && !(p->stim == STIM_WATCHDOG && frame >= 100u);
      if (streaming) usb_frame(mode, 0u, frame);
    }
    if (p->stim == STIM_ESTOP && i == 1000u) GPIOB->IDR |= 1u << 8; /* the E-stop loop opens */
    /* The tool moves out and back: both directions, reversals, rest. */
    const int32_t phase = (int32_t)(i % 2000u);
    const int32_t ins = phase < 900 ? 3 : phase < 1000 ? 0 : phase < 1900 ? -3 : 0;
    board_period(&config, ins, ins > 0 ? -1 : ins < 0 ? 1 : 0, &edge_cost);
    MEASURE(&tick, systick());
    cbx_state_report s;
    cbx_core_state(&core, &s);
    switch (p->stim) {
      case STIM_RENDER: reached |= (s.status & CBX_STATUS_OUTPUT_ENABLED) != 0u; break;
      case STIM_ESTOP: reached |= (s.faults & CBX_FAULT_ESTOP) != 0u && s.insertion_force_mN == 0; break;
      case STIM_WATCHDOG: reached |= (s.faults & CBX_FAULT_WATCHDOG) != 0u; break;
      case STIM_SELFTEST: reached |= (s.status & CBX_STATUS_SELFTEST_RUNNING) != 0u && TIM4->CCR1 != 0u; break;
    }
  }
  report(&tick, true);
  if (!reached) printf("tick cost: operating point '%s' did not reach the state it measures\n", p->name);
  return reached;
}

/* New calibration or limits arrive while both axes render: the tick that takes them. */
static bool run_settings_point(void) {
  const cbx_core_config config = board_config(CBX_ACTUATOR_MOTOR, CBX_ENCODER_COUNTER);
  (void)started(&config);
  cost tick = {"tick applying new calibration / limits (rendering)", 0, 0, 0};
  bool rendering = true;
  for (uint32_t i = 0; i < 40u + 20u * SETTINGS_CHANGES; ++i) {
    if (i % 10u == 0u) usb_frame(CBX_MODE_MOTOR, 0u, i / 10u);
    const bool change = i >= 40u && i % 20u == 0u;
    if (change) {
      const uint32_t k = i / 20u;
      if (k % 2u == 0u) {
        const cbx_calibration c = calibration(100000u + 37u * k);
        usb_feature(CBX_ID_CALIBRATION, &c);
      } else {
        const cbx_limits l = limits(4000u + 10u * k);
        usb_feature(CBX_ID_LIMITS, &l);
      }
    }
    board_period(&config, 3, -1, &edge_cost);
    if (change) MEASURE(&tick, systick());
    else systick();
    cbx_state_report s;
    cbx_core_state(&core, &s);
    if (i >= 40u && !(s.status & CBX_STATUS_OUTPUT_ENABLED)) rendering = false;
  }
  report(&tick, true);
  if (!rendering) printf("tick cost: the output stopped while settings changed\n");
  return rendering;
}

int main(void) {
  calibrate_counter();
  static const operating_point points[] = {
      {"tick: brake, counter encoders, rendering", CBX_ACTUATOR_BRAKE, CBX_ENCODER_COUNTER, STIM_RENDER},
      {"tick: motor, counter encoders, rendering", CBX_ACTUATOR_MOTOR, CBX_ENCODER_COUNTER, STIM_RENDER},
      {"tick: motor, raw-edge encoders, rendering", CBX_ACTUATOR_MOTOR, CBX_ENCODER_EDGES, STIM_RENDER},
      {"tick: brake, raw-edge encoders, rendering", CBX_ACTUATOR_BRAKE, CBX_ENCODER_EDGES, STIM_RENDER},
      {"tick: motor, E-stop fault latched (output cut)", CBX_ACTUATOR_MOTOR, CBX_ENCODER_COUNTER, STIM_ESTOP},
      {"tick: motor, watchdog ramp then fault latched", CBX_ACTUATOR_MOTOR, CBX_ENCODER_COUNTER, STIM_WATCHDOG},
      {"tick: brake, self-test drive", CBX_ACTUATOR_BRAKE, CBX_ENCODER_COUNTER, STIM_SELFTEST},
  };
  printf("firmware on Cortex-M4 (QEMU -icount), STM32F411 port HAL with registers in RAM; "
         "instructions (counter resolution %lu.%02lu instructions); budget %u per tick\n",
         (unsigned long)(loop_insns / loop_counts), (unsigned long)(loop_insns % loop_counts * 100u / loop_counts),
         TICK_BUDGET);
  bool reached = true;
  for (unsigned i = 0; i < sizeof points / sizeof points[0]; ++i) reached &= run_point(&points[i]);
  reached &= run_settings_point();
  report(&decode_cost, true);
  report(&state_cost, true);
  report(&edge_cost, true);
  report(&feature_cost, false);
  if (!reached) return 2;
  if (over_budget) {
    printf("tick cost: over the budget of %u instructions\n", TICK_BUDGET);
    return 1;
  }
  printf("tick cost: every worst case within %u instructions\n", TICK_BUDGET);
  return 0;
}
