#pragma once
// The one place that maps between the three frames a hand-held tool lives in:
//
//   box counts ──calibration──▶ calibrated µm / µrad of the box (from the box's count zero)
//              ──count origin─▶ the hand's position: µm / µrad since the session started
//              ──tool offset──▶ the held tool's insertion / rotation in the session (µm, µrad)
//
// and back, for the force law the box renders (session mm ─▶ the box's mm from its count zero).
// A hand that holds one tool at a time (box, keyboard, autopilot) owns one. Taking another
// tool (hold()) sets that tool's offset so it carries on from where it is; the keyboard moves
// the held tool by nudging its offset. Hands without encoders (keyboard, autopilot) use the
// default mapping: no calibration, hand positions come in µm / µrad already.
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>

#include "session/hand.hpp"
#include "tool/force_law.hpp"

namespace cathbox::session {

// The box's encoder calibration (its calibration feature report).
struct EncoderCalibration {
  std::uint32_t insertion_counts_per_m = 0;
  std::uint32_t rotation_counts_per_rev = 0;
  [[nodiscard]] bool valid() const { return insertion_counts_per_m > 0 && rotation_counts_per_rev > 0; }
};

// How far the hand has pushed and turned since the session started.
struct HandPosition {
  std::int64_t insertion_um = 0;
  std::int64_t rotation_urad = 0;
  friend bool operator==(const HandPosition&, const HandPosition&) = default;
};

struct BoxCounts {
  std::int64_t insertion = 0;
  std::int64_t rotation = 0;
  friend bool operator==(const BoxCounts&, const BoxCounts&) = default;
};

class HandMapping {
 public:
  HandMapping() = default;
  explicit HandMapping(EncoderCalibration calibration) : calibration_(calibration) {}

  [[nodiscard]] const EncoderCalibration& calibration() const { return calibration_; }

  // Counts <-> calibrated micrometres / microradians of the box (rounded to the nearest).
  [[nodiscard]] std::int64_t insertion_um_from_counts(std::int64_t counts) const;
  [[nodiscard]] std::int64_t rotation_urad_from_counts(std::int64_t counts) const;
  [[nodiscard]] std::int64_t insertion_counts_from_um(std::int64_t um) const;
  [[nodiscard]] std::int64_t rotation_counts_from_urad(std::int64_t urad) const;
  // Counts (or counts per second) -> calibrated millimetres (per second) / radians (per second)
  // of the box, unrounded, for display (`cathbox monitor`); 0 without a calibration.
  [[nodiscard]] double insertion_mm_from_counts(double counts) const;
  [[nodiscard]] double rotation_rad_from_counts(double counts) const;

  // The box's counts when the session started (its first state); until then positions are 0.
  void set_count_origin(BoxCounts origin) {
    origin_ = origin;
    has_origin_ = true;
  }
  [[nodiscard]] bool has_count_origin() const { return has_origin_; }
  [[nodiscard]] HandPosition hand_from_counts(BoxCounts counts) const;
  [[nodiscard]] BoxCounts counts_from_hand(HandPosition hand) const;

  // The held tool's command for a hand position (remembered for hold() and nudge()).
  [[nodiscard]] ToolCommand command(HandPosition hand);
  // The hand now holds `tool`, which is at `at`: from now on command(hand) continues from there.
  void hold(std::size_t tool, const ToolCommand& at);
  [[nodiscard]] std::size_t held() const { return held_; }
  // Moves the held tool without moving the hand (keyboard on top of the box), keeping its
  // insertion within [0, max_insertion_um] (a nudge beyond is cut, so there is no dead zone).
  void nudge(std::int64_t insertion_um, std::int64_t rotation_urad, std::int64_t max_insertion_um);
  [[nodiscard]] const ToolCommand& offset() const { return offset_; }

  // The held tool's force law (session millimetres and radians) in the box's own frame: its
  // positions measured from the box's count zero, as device::force_law_command takes it.
  [[nodiscard]] tool::ForceLaw law_to_box(const tool::ForceLaw& session_law) const;
  // The box's calibrated position (mm / rad from its count zero) of a session position of the
  // held tool: what law_to_box does to insertion0 / rotation0.
  [[nodiscard]] std::pair<double, double> box_from_session(double insertion_mm, double rotation_rad) const;

 private:
  [[nodiscard]] std::int64_t origin_insertion_um() const;
  [[nodiscard]] std::int64_t origin_rotation_urad() const;

  EncoderCalibration calibration_;
  BoxCounts origin_;
  bool has_origin_ = false;
  HandPosition last_hand_;
  ToolCommand offset_;  // held tool = hand + offset
  std::size_t held_ = 0;
};

}  // namespace cathbox::session
