#include "session/hand_mapping.hpp"

#include <algorithm>
#include <cmath>

namespace cathbox::session {
namespace {

constexpr double kTwoPi = 6.283185307179586;

__extension__ typedef __int128 Wide;  // GCC and Clang: exact products of two 64-bit values

// round(value * num / den) for a positive den (halves away from zero), exact.
std::int64_t scale_rounded(std::int64_t value, std::int64_t num, std::int64_t den) {
  if (den <= 0) return 0;
  const Wide p = static_cast<Wide>(value) * num;
  const Wide half = den / 2;
  const Wide q = p >= 0 ? (p + half) / den : -((-p + half) / den);
  return static_cast<std::int64_t>(q);
}

}  // namespace

// 1 m = 1e6 um: um = counts * 1e6 / counts_per_m.
std::int64_t HandMapping::insertion_um_from_counts(std::int64_t counts) const {
  return scale_rounded(counts, 1'000'000, calibration_.insertion_counts_per_m);
}

std::int64_t HandMapping::insertion_counts_from_um(std::int64_t um) const {
  return scale_rounded(um, calibration_.insertion_counts_per_m, 1'000'000);
}

// One revolution = 2 pi rad: urad = counts * 2 pi 1e6 / counts_per_rev.
std::int64_t HandMapping::rotation_urad_from_counts(std::int64_t counts) const {
  if (calibration_.rotation_counts_per_rev == 0) return 0;
  return std::llround(static_cast<double>(counts) * kTwoPi * 1e6 / calibration_.rotation_counts_per_rev);
}

std::int64_t HandMapping::rotation_counts_from_urad(std::int64_t urad) const {
  return std::llround(static_cast<double>(urad) * 1e-6 / kTwoPi * calibration_.rotation_counts_per_rev);
}

double HandMapping::insertion_mm_from_counts(double counts) const {
  if (calibration_.insertion_counts_per_m == 0) return 0.0;
  return counts / (calibration_.insertion_counts_per_m / 1000.0);
}

double HandMapping::rotation_rad_from_counts(double counts) const {
  if (calibration_.rotation_counts_per_rev == 0) return 0.0;
  return counts * kTwoPi / calibration_.rotation_counts_per_rev;
}

std::int64_t HandMapping::origin_insertion_um() const { return insertion_um_from_counts(origin_.insertion); }
std::int64_t HandMapping::origin_rotation_urad() const { return rotation_urad_from_counts(origin_.rotation); }

HandPosition HandMapping::hand_from_counts(BoxCounts counts) const {
  if (!has_origin_) return {};
  return {insertion_um_from_counts(counts.insertion) - origin_insertion_um(),
          rotation_urad_from_counts(counts.rotation) - origin_rotation_urad()};
}

BoxCounts HandMapping::counts_from_hand(HandPosition hand) const {
  return {insertion_counts_from_um(hand.insertion_um + origin_insertion_um()),
          rotation_counts_from_urad(hand.rotation_urad + origin_rotation_urad())};
}

ToolCommand HandMapping::command(HandPosition hand) {
  last_hand_ = hand;
  return {hand.insertion_um + offset_.insertion_um, hand.rotation_urad + offset_.rotation_urad};
}

void HandMapping::hold(std::size_t tool, const ToolCommand& at) {
  held_ = tool;
  offset_ = {at.insertion_um - last_hand_.insertion_um, at.rotation_urad - last_hand_.rotation_urad};
}

void HandMapping::nudge(std::int64_t insertion_um, std::int64_t rotation_urad, std::int64_t max_insertion_um) {
  const std::int64_t now = last_hand_.insertion_um + offset_.insertion_um;
  const std::int64_t wanted = std::clamp(now + insertion_um, std::int64_t{0}, std::max<std::int64_t>(0, max_insertion_um));
  // Never pull a tool that is beyond its range further out of it.
  const std::int64_t moved = insertion_um >= 0 ? std::max<std::int64_t>(0, wanted - now) : std::min<std::int64_t>(0, wanted - now);
  offset_.insertion_um += moved;
  offset_.rotation_urad += rotation_urad;
}

std::pair<double, double> HandMapping::box_from_session(double insertion_mm, double rotation_rad) const {
  // box = session - offset + origin (all in the box's calibrated frame).
  const double ins_mm = insertion_mm - static_cast<double>(offset_.insertion_um - origin_insertion_um()) * 1e-3;
  const double rot_rad = rotation_rad - static_cast<double>(offset_.rotation_urad - origin_rotation_urad()) * 1e-6;
  return {ins_mm, rot_rad};
}

tool::ForceLaw HandMapping::law_to_box(const tool::ForceLaw& session_law) const {
  tool::ForceLaw law = session_law;
  const auto [ins, rot] = box_from_session(session_law.insertion0_mm, session_law.rotation0_rad);
  law.insertion0_mm = ins;
  law.rotation0_rad = rot;
  return law;
}

}  // namespace cathbox::session
