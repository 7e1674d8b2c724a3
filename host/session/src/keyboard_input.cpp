#include "session/keyboard_input.hpp"

#include <cmath>

namespace cathbox::session {
namespace {

// Whole units of `rest + speed * dt`; the fraction stays in `rest`.
std::int64_t whole(double& rest, double amount) {
  rest += std::isfinite(amount) ? amount : 0.0;
  const double w = std::trunc(rest);
  rest -= w;
  return static_cast<std::int64_t>(w);
}

}  // namespace

KeyboardInput::Motion KeyboardInput::take(double dt_s) {
  Motion m;
  m.insertion_um = whole(insertion_rest_um_, insert_mm_s_.load(std::memory_order_relaxed) * dt_s * 1e3);
  m.rotation_urad = whole(rotation_rest_urad_, rotate_rad_s_.load(std::memory_order_relaxed) * dt_s * 1e6);
  return m;
}

}  // namespace cathbox::session
