#pragma once
// A balloon on a catheter and the inflation device that fills it. The balloon's diameter
// follows its compliance chart (BalloonSpec: diameter at each pressure, linear between the
// printed points and along the last slope beyond them; below the chart's first pressure the
// folded balloon unfolds from the shaft diameter). Its volume is that of its working length as
// a cylinder. The inflation device moves the pressure towards the target at a hand's rate
// (kInflateRate_atm_s) and pulls vacuum to deflate (kDeflateRate_atm_s); a target volume is
// turned into the pressure that gives it. Counts inflations and their time, the largest
// pressure, and whether the rated burst pressure was exceeded.
#include <cstdint>

#include "tool/tool_spec.hpp"

namespace cathbox::tool {

class Balloon {
 public:
  static constexpr double kInflateRate_atm_s = 2.0;   // a hand turning the indeflator's screw
  static constexpr double kDeflateRate_atm_s = 10.0;  // vacuum
  // An inflation counts above 1 atm, or above the chart's first pressure if that is lower: a
  // compliant remodelling balloon (chart from 0.5 atm) is up at 1 atm, a semi-compliant
  // angioplasty balloon (chart from 2 atm) still folded.
  static constexpr double kInflatedAbove_atm = 1.0;
  static constexpr double kMaxPressure_atm = 30.0;    // what an inflation device reaches
  static constexpr double kAtm_N_per_mm2 = 0.101325;

  Balloon(const BalloonSpec& spec, double shaft_diameter_mm);

  void set_target_pressure(double pressure_atm);
  void set_target_volume(double volume_ml);
  void deflate() { target_atm_ = 0.0; }
  void step(double dt_s);

  [[nodiscard]] double pressure_atm() const { return pressure_atm_; }
  [[nodiscard]] double target_atm() const { return target_atm_; }
  [[nodiscard]] bool inflated() const { return pressure_atm_ > inflated_above_atm_; }
  // Unconstrained diameter and volume at the present pressure.
  [[nodiscard]] double diameter_mm() const { return diameter_at(pressure_atm_); }
  [[nodiscard]] double volume_ml() const { return volume_at(pressure_atm_); }
  [[nodiscard]] double diameter_at(double pressure_atm) const;
  [[nodiscard]] double volume_at(double pressure_atm) const;
  // Pressure that holds `volume_ml` (the inverse of volume_at; clamped to [0, kMaxPressure]).
  [[nodiscard]] double pressure_for_volume(double volume_ml) const;
  [[nodiscard]] const BalloonSpec& spec() const { return spec_; }

  // Metrics.
  [[nodiscard]] int inflations() const { return inflations_; }
  [[nodiscard]] double inflated_time_s() const { return inflated_time_s_; }
  [[nodiscard]] double max_pressure_atm() const { return max_pressure_atm_; }
  [[nodiscard]] bool exceeded_rated_burst() const { return over_rated_burst_; }

 private:
  BalloonSpec spec_;
  double shaft_diameter_mm_;
  double inflated_above_atm_ = kInflatedAbove_atm;
  double pressure_atm_ = 0.0;
  double target_atm_ = 0.0;
  int inflations_ = 0;
  bool was_inflated_ = false;
  double inflated_time_s_ = 0.0;
  double max_pressure_atm_ = 0.0;
  bool over_rated_burst_ = false;
};

}  // namespace cathbox::tool
