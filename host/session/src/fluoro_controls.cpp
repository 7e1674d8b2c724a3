#include "session/fluoro_controls.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "base/bit_cast.hpp"

namespace cathbox::session::fluoro_control {
namespace {

// Up to four f64 values, little-endian, as one control.
template <std::size_t N>
Control make_f64(ControlKind kind, const std::array<double, N>& values) {
  std::array<std::uint8_t, 8 * N> bytes{};
  for (std::size_t i = 0; i < N; ++i) {
    const auto bits = base::bit_cast<std::uint64_t>(values[i]);
    for (std::size_t b = 0; b < 8; ++b) bytes[8 * i + b] = static_cast<std::uint8_t>(bits >> (8 * b));
  }
  return Control::make(static_cast<std::uint16_t>(kind), bytes);
}

template <std::size_t N>
std::optional<std::array<double, N>> read_f64(const Control& c) {
  if (c.size != 8 * N) return std::nullopt;
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i) {
    std::uint64_t bits = 0;
    for (std::size_t b = 0; b < 8; ++b) bits |= static_cast<std::uint64_t>(c.payload[8 * i + b]) << (8 * b);
    out[i] = base::bit_cast<double>(bits);
    if (!std::isfinite(out[i])) return std::nullopt;
  }
  return out;
}

Control make_flag(ControlKind kind, bool on) {
  const std::uint8_t b = on ? 1 : 0;
  return Control::make(static_cast<std::uint16_t>(kind), std::span(&b, 1));
}

}  // namespace

Control pedal(bool pressed) { return make_flag(ControlKind::kFluoroPedal, pressed); }
Control roadmap(bool capture) { return make_flag(ControlKind::kRoadmap, capture); }

Control inject(double volume_ml, double rate_ml_s, double concentration_mgI_ml) {
  if (concentration_mgI_ml == kDefaultContrast_mgI_ml) return make_f64(ControlKind::kInject, std::array{volume_ml, rate_ml_s});
  return make_f64(ControlKind::kInject, std::array{volume_ml, rate_ml_s, concentration_mgI_ml});
}

Control carm_angles(double lao_deg, double cranial_deg) {
  return make_f64(ControlKind::kCArmAngles, std::array{lao_deg, cranial_deg});
}

Control carm_geometry(double sid_mm, double table_height_mm, double fov_mm, double collimation) {
  return make_f64(ControlKind::kCArmGeometry, std::array{sid_mm, table_height_mm, fov_mm, collimation});
}

Control pulse_rate(double per_s) {
  const auto tenths = static_cast<std::uint16_t>(std::clamp(std::lround(per_s * 10.0), 0L, 65535L));
  const std::array<std::uint8_t, 2> b{static_cast<std::uint8_t>(tenths & 0xFF), static_cast<std::uint8_t>(tenths >> 8)};
  return Control::make(static_cast<std::uint16_t>(ControlKind::kPulseRate), b);
}

std::optional<Control> from_action(const tool::Action& a) {
  switch (a.kind) {
    case tool::ActionKind::kFluoro: return pedal(a.value != 0.0);
    case tool::ActionKind::kInject:
      return inject(a.value, a.speed, a.concentration_mgI_ml > 0.0 ? a.concentration_mgI_ml : kDefaultContrast_mgI_ml);
    case tool::ActionKind::kCArm: return carm_angles(a.value, a.value2);
    case tool::ActionKind::kRoadmap: return roadmap(a.value != 0.0);
    default: return std::nullopt;
  }
}

std::optional<bool> read_flag(const Control& c) {
  if (c.size != 1 || c.payload[0] > 1) return std::nullopt;
  return c.payload[0] == 1;
}

std::optional<InjectPayload> read_inject(const Control& c) {
  if (const auto v = read_f64<3>(c)) return InjectPayload{(*v)[0], (*v)[1], (*v)[2]};
  const auto v = read_f64<2>(c);
  if (!v) return std::nullopt;
  return InjectPayload{(*v)[0], (*v)[1]};
}

std::optional<AnglesPayload> read_angles(const Control& c) {
  const auto v = read_f64<2>(c);
  if (!v) return std::nullopt;
  return AnglesPayload{(*v)[0], (*v)[1]};
}

std::optional<GeometryPayload> read_geometry(const Control& c) {
  const auto v = read_f64<4>(c);
  if (!v) return std::nullopt;
  return GeometryPayload{(*v)[0], (*v)[1], (*v)[2], (*v)[3]};
}

std::optional<double> read_pulse_rate(const Control& c) {
  if (c.size != 2) return std::nullopt;
  return static_cast<double>(c.payload[0] | (c.payload[1] << 8)) / 10.0;
}

}  // namespace cathbox::session::fluoro_control
