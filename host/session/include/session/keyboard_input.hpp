#pragma once
// The keyboard and mouse as a source of motion: the render thread sets insertion and rotation
// speeds (atomics, never blocking); the haptic thread takes, once per tick, how far they moved
// the tool in that tick, in whole micrometres and microradians (the fractions are carried over,
// so slow speeds are not lost to rounding).
#include <atomic>
#include <cstdint>

namespace cathbox::session {

class KeyboardInput {
 public:
  // Render thread.
  void set_speeds(double insert_mm_s, double rotate_rad_s) {
    insert_mm_s_.store(insert_mm_s, std::memory_order_relaxed);
    rotate_rad_s_.store(rotate_rad_s, std::memory_order_relaxed);
  }

  struct Motion {
    std::int64_t insertion_um = 0;
    std::int64_t rotation_urad = 0;
  };
  // Haptic thread: the motion of one tick of dt seconds.
  [[nodiscard]] Motion take(double dt_s);

 private:
  std::atomic<double> insert_mm_s_{0.0};
  std::atomic<double> rotate_rad_s_{0.0};
  double insertion_rest_um_ = 0.0;
  double rotation_rest_urad_ = 0.0;
};

}  // namespace cathbox::session
