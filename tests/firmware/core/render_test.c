/* The force pipeline pieces: calibration scaling, force law, clamps, brake passivity, slew and
 * the output curve. */
#include "cbx_test.h"
#include "cbx_vectors.h"
#include "fake_hal.h"
#include "firmware/cbx_render.h"

static const cbx_curve_point identity[CBX_CURVE_POINTS] = {{250, 250}, {500, 500}, {750, 750}, {1000, 1000}};

static void position_scaling(void) {
  cbx_axis_scale s;
  cbx_axis_scale_set(&s, 40000u, 1000000u, 8000u, identity, 5000u, 100u);
  CBX_CHECK(s.valid);
  CBX_CHECK_EQ(cbx_axis_scale_position(&s, 1), 25);
  CBX_CHECK_EQ(cbx_axis_scale_position(&s, -40000), -1000000);
  CBX_CHECK_EQ(cbx_axis_scale_position(&s, 4000000), 100000000);
  CBX_CHECK_EQ(cbx_axis_scale_position(&s, INT32_MAX), INT32_MAX); /* saturates */
  CBX_CHECK_EQ(cbx_axis_scale_position(&s, INT32_MIN), INT32_MIN);
  /* Rotation: 4096 counts per revolution, 2*pi*1e6 urad. */
  cbx_axis_scale_set(&s, 4096u, 6283185u, 20000u, identity, 50000u, 1000u);
  CBX_CHECK_NEAR(cbx_axis_scale_position(&s, 1024), 1570796, 1);
  CBX_CHECK_NEAR(cbx_axis_scale_position(&s, -2048), -3141593, 1);
  /* No calibration: not valid. */
  cbx_axis_scale_set(&s, 0u, 1000000u, 8000u, identity, 5000u, 100u);
  CBX_CHECK(!s.valid);
  CBX_CHECK_EQ(cbx_render_drive(&s, CBX_MODE_MOTOR, 1000), 0);
}

static void law_through_scaling(void) {
  /* The golden brake law (offset -200 mN, pos0 250 mm, k 400 N/m, b 2 N*s/m, clamp [-3000, 0])
   * evaluated at positions and velocities that come from encoder counts (40000 counts/m). */
  const cbx_vector* v = cbx_fake_vector("command_brake_law");
  if (!v) return;
  const cbx_force_law* law = &v->value.command.insertion;
  cbx_axis_scale s;
  cbx_axis_scale_set(&s, 40000u, 1000000u, 8000u, identity, 5000u, 100u);
  const int32_t pos = cbx_axis_scale_position(&s, 10400); /* 260 mm */
  const int32_t vel = cbx_axis_scale_position(&s, 400);   /* 10 mm/s */
  CBX_CHECK_EQ(pos, 260000);
  CBX_CHECK_EQ(vel, 10000);
  CBX_CHECK_EQ(cbx_force_law_eval(law, pos, vel), -3000); /* -200 - 4000 - 20, clamped */
  CBX_CHECK_EQ(cbx_force_law_eval(law, cbx_axis_scale_position(&s, 10040), 0), -600); /* 251 mm */
  CBX_CHECK_EQ(cbx_force_law_eval(law, cbx_axis_scale_position(&s, 9600), 0), 0);    /* outside */
  CBX_CHECK_EQ(cbx_force_law_eval(law, 250500, cbx_axis_scale_position(&s, -400)), -380);
}

static void clamp_and_brake_passivity(void) {
  cbx_axis_scale s;
  cbx_axis_scale_set(&s, 40000u, 1000000u, 8000u, identity, 5000u, 100u);
  CBX_CHECK_EQ(cbx_render_target(&s, CBX_MODE_MOTOR, 9000, 0), 5000);
  CBX_CHECK_EQ(cbx_render_target(&s, CBX_MODE_MOTOR, -9000, 0), -5000);
  CBX_CHECK_EQ(cbx_render_target(&s, CBX_MODE_MOTOR, 700, 1000), 700);   /* motor may push */
  CBX_CHECK_EQ(cbx_render_target(&s, CBX_MODE_BRAKE, 700, 1000), 0);     /* brake may not */
  CBX_CHECK_EQ(cbx_render_target(&s, CBX_MODE_BRAKE, -700, 1000), -700);  /* opposes motion */
  CBX_CHECK_EQ(cbx_render_target(&s, CBX_MODE_BRAKE, 700, -1000), 700);
  CBX_CHECK_EQ(cbx_render_target(&s, CBX_MODE_BRAKE, -700, -1000), 0);
  CBX_CHECK_EQ(cbx_render_target(&s, CBX_MODE_BRAKE, 700, 0), 700);       /* holds at rest */
  CBX_CHECK_EQ(cbx_render_target(&s, CBX_MODE_OFF, 700, 0), 0);
}

static void slew_limits_steps(void) {
  CBX_CHECK_EQ(cbx_render_slew(0, 1000, 10), 10);
  CBX_CHECK_EQ(cbx_render_slew(995, 1000, 10), 1000);
  CBX_CHECK_EQ(cbx_render_slew(0, -1000, 10), -10);
  CBX_CHECK_EQ(cbx_render_slew(INT32_MIN, INT32_MAX, INT32_MAX), -1);
  CBX_CHECK_EQ(cbx_render_slew(5, 5, 0), 5);
}

static void drive_through_curve(void) {
  const cbx_vector* v = cbx_fake_vector("calibration_brake");
  if (!v) return;
  const cbx_calibration* c = &v->value.calibration;
  cbx_axis_scale s;
  cbx_axis_scale_set(&s, c->insertion_counts_per_m, 1000000u, c->insertion_full_scale_mN,
                     c->insertion_curve, 50000u, 100u);
  /* 3600 mN of 12000 = 300 per mille -> curve point (300, 390). */
  CBX_CHECK_EQ(cbx_render_drive(&s, CBX_MODE_BRAKE, 3600), 390);
  CBX_CHECK_EQ(cbx_render_drive(&s, CBX_MODE_BRAKE, -3600), 390); /* a brake takes magnitude */
  CBX_CHECK_EQ(cbx_render_drive(&s, CBX_MODE_MOTOR, -3600), -390);
  CBX_CHECK_EQ(cbx_render_drive(&s, CBX_MODE_MOTOR, 600), 90);  /* 50 per mille: half of (100,180) */
  CBX_CHECK_EQ(cbx_render_drive(&s, CBX_MODE_MOTOR, 40000), 1000); /* beyond full scale */
  CBX_CHECK_EQ(cbx_render_drive(&s, CBX_MODE_OFF, 3600), 0);
}

const cbx_test_case cbx_tests_render[] = {
    {"position_scaling", position_scaling},
    {"law_through_scaling", law_through_scaling},
    {"clamp_and_brake_passivity", clamp_and_brake_passivity},
    {"slew_limits_steps", slew_limits_steps},
    {"drive_through_curve", drive_through_curve},
    {0, 0}};
