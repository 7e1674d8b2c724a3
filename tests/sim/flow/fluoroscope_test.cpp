#include "flow/fluoroscope.hpp"

#include <gtest/gtest.h>

#include "flow_test_support.hpp"

namespace cathbox::flow {
namespace {

// Ticks the unit at 1 kHz from `from` to `to` (exclusive) and counts pulses.
int run_ms(Fluoroscope& f, std::int64_t& now_us, int ms, bool injecting = false) {
  int pulses = 0;
  for (int i = 0; i < ms; ++i, now_us += 1000) pulses += f.tick(now_us, injecting).pulsed ? 1 : 0;
  return pulses;
}

TEST(Fluoroscope, PulsesAtTheRateWhileThePedalIsDownAndHoldsTheLastImage) {
  Fluoroscope f;
  std::int64_t now = 0;
  EXPECT_EQ(run_ms(f, now, 500), 0);
  EXPECT_EQ(f.image().pulse, -1);
  f.set_pedal(true);
  EXPECT_EQ(run_ms(f, now, 1000), 15);  // 15 pulses/s: at 0, 66.7, ..., 933.3 ms
  EXPECT_TRUE(f.image().beam_on);
  EXPECT_EQ(f.image().pulse, 14);
  // Due round(14e6 / 15) = 933333 us after the press; it fires at the first 1 ms tick after that.
  EXPECT_EQ(f.image().pulse_time_us, 500'000 + 934'000);
  f.set_pedal(false);
  EXPECT_EQ(run_ms(f, now, 800), 0);
  EXPECT_TRUE(f.image().last_image_hold());
  EXPECT_EQ(f.image().pulse, 14);
  EXPECT_NEAR(f.metrics().fluoro_time_s, 1.0, 1e-9);
  EXPECT_EQ(f.metrics().pulses, 15);
  EXPECT_EQ(f.metrics().runs, 0);
  // 7.5 and 30 pulses/s.
  ASSERT_EQ(f.set_pulse_rate(7.5), "");
  f.set_pedal(true);
  EXPECT_EQ(run_ms(f, now, 1000), 8);
  ASSERT_EQ(f.set_pulse_rate(30.0), "");  // the train goes on from the last pulse
  EXPECT_NEAR(run_ms(f, now, 3000), 90, 1);
  EXPECT_EQ(f.set_pulse_rate(10.0), "pulse rate must be 7.5, 15 or 30 pulses per second");
  EXPECT_EQ(f.pulse_rate(), 30.0);
}

TEST(Fluoroscope, DoseAreaProductAddsUpPerPulse) {
  Fluoroscope f;
  const double per_pulse = f.dose().dap_per_pulse_Gy_cm2(ExposureMode::kFluoroscopy, f.carm().field_area_cm2(),
                                                         f.patient_transmission());
  std::int64_t now = 0;
  f.set_pedal(true);
  run_ms(f, now, 2000);
  EXPECT_NEAR(f.metrics().dap_Gy_cm2, 30.0 * per_pulse, 1e-12);
  // Of the order of 1-3 Gy cm^2 per minute of 15 p/s fluoroscopy through the head.
  EXPECT_GT(per_pulse * 15.0 * 60.0, 0.3);
  EXPECT_LT(per_pulse * 15.0 * 60.0, 10.0);
  // Collimating to half the field quarters the dose-area product of a pulse.
  CArmPose p;
  p.collimation = 0.5;
  ASSERT_EQ(f.set_pose(p), "");
  EXPECT_NEAR(f.dose().dap_per_pulse_Gy_cm2(ExposureMode::kFluoroscopy, f.carm().field_area_cm2(), f.patient_transmission()),
              0.25 * per_pulse * Fluoroscope().patient_transmission() / f.patient_transmission(), 1e-12);
}

TEST(Fluoroscope, ContrastRunMaskPeakAndRoadmap) {
  Fluoroscope f;
  std::int64_t now = 0;
  f.set_pedal(true);
  run_ms(f, now, 300);  // pulses 0..4 of plain fluoroscopy
  EXPECT_EQ(f.image().run, 0);
  EXPECT_FALSE(f.capture_roadmap());  // no run yet
  // Inject: the next pulse starts run 1 with the previous pulse as its mask.
  std::vector<double> iodine{1.0, 5.0, 9.0, 7.0, 2.0};
  int seen = 0;
  std::int64_t first_run_pulse = -1;
  for (int i = 0; i < 400; ++i, now += 1000) {
    const FluoroTick t = f.tick(now, true);
    if (!t.pulsed) continue;
    if (t.run_started) first_run_pulse = t.pulse;
    f.report_iodine_in_field(t.pulse, seen < 5 ? iodine[static_cast<std::size_t>(seen)] : 0.5);
    ++seen;
  }
  EXPECT_EQ(f.metrics().runs, 1);
  EXPECT_EQ(first_run_pulse, 5);
  EXPECT_EQ(f.image().run, 1);
  EXPECT_EQ(f.image().mask_pulse, 4);
  EXPECT_TRUE(f.image().subtracted());
  EXPECT_EQ(f.image().mode, ExposureMode::kSubtractionRun);
  EXPECT_EQ(f.peak_pulse(), first_run_pulse + 2);  // 9 mg
  // The run continues after the injection until the pedal is released.
  run_ms(f, now, 200, false);
  EXPECT_EQ(f.image().run, 1);
  f.set_pedal(false);
  run_ms(f, now, 10);
  EXPECT_TRUE(f.capture_roadmap());
  EXPECT_EQ(f.image().roadmap_pulse, first_run_pulse + 2);
  // Plain fluoroscopy again, with the roadmap overlaid.
  f.set_pedal(true);
  run_ms(f, now, 100);
  EXPECT_EQ(f.image().run, 0);
  EXPECT_EQ(f.image().roadmap_pulse, first_run_pulse + 2);
  EXPECT_EQ(f.metrics().runs, 1);
  // A second run with the pedal pressed during an injection.
  f.set_pedal(false);
  run_ms(f, now, 10);
  f.set_pedal(true);
  run_ms(f, now, 100, true);
  EXPECT_EQ(f.metrics().runs, 2);
  EXPECT_EQ(f.image().mask_pulse, f.image().pulse - 1);  // the first pulse is its own mask's successor
  f.clear_roadmap();
  EXPECT_EQ(f.image().roadmap_pulse, -1);
}

TEST(Fluoroscope, MovingTheCArmRemovesTheRoadmap) {
  Fluoroscope f;
  std::int64_t now = 0;
  f.set_pedal(true);
  for (int i = 0; i < 300; ++i, now += 1000) {
    const FluoroTick t = f.tick(now, true);
    if (t.pulsed) f.report_iodine_in_field(t.pulse, 1.0 + i);
  }
  f.set_pedal(false);
  run_ms(f, now, 5);
  ASSERT_TRUE(f.capture_roadmap());
  CArmPose p;
  p.lao_deg = 30.0;
  ASSERT_EQ(f.set_pose(p), "");
  EXPECT_EQ(f.image().roadmap_pulse, -1);
  EXPECT_FALSE(f.capture_roadmap());  // the run was made at another angle
  p.lao_deg = 200.0;
  EXPECT_NE(f.set_pose(p), "");
  EXPECT_EQ(f.carm().pose().lao_deg, 30.0);
}

TEST(FieldIodine, CountsTheContrastInTheField) {
  const auto net = test::build_or_fail(test::load_model("cases/neuro.hclm"));
  ContrastTransport t(*net);
  std::uint32_t ica = 0;
  for (std::uint32_t i = 0; i < net->model().segments.size(); ++i) {
    if (net->model().segments[i].name == "right_internal_carotid") ica = i;
  }
  ASSERT_EQ(t.inject({ica, 40.0, 0.0}, Injection{2.0, 4.0, 300.0}), "");
  for (int i = 0; i < 30; ++i) t.step();
  const FieldIodine field(t);
  CArmPose wide;
  wide.fov_mm = 420.0;
  wide.isocenter_mm = {0, 10, 200};
  const double all = field.in_field_mg(t, CArm(wide));
  EXPECT_NEAR(all, t.in_vessels_mg(), 1e-6 * t.in_vessels_mg());  // everything is in a 42 cm field
  CArmPose narrow;
  narrow.collimation = 0.2;
  narrow.isocenter_mm = {60, 10, -100};  // the chest, away from the head
  EXPECT_EQ(field.in_field_mg(t, CArm(narrow)), 0.0);
}

}  // namespace
}  // namespace cathbox::flow
