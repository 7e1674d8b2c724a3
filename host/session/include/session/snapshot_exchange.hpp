#pragma once
// Triple buffer between one writer (the haptic thread) and one reader (the render thread).
// Both sides are wait-free: the writer fills its private slot and publishes it with one atomic
// exchange; the reader takes the newest published slot with another. Neither ever waits for
// the other, so rendering can never stall the haptic loop.
#include <array>
#include <atomic>
#include <cstdint>

namespace cathbox::session {

template <class T>
class SnapshotExchange {
 public:
  SnapshotExchange() = default;
  explicit SnapshotExchange(const T& initial) : slots_{initial, initial, initial} {}

  // Prepares every slot before the threads start (e.g. reserves vectors, which copies would
  // not carry over, so that publishing never allocates).
  template <class Fn>
  void prepare_slots(Fn&& prepare) {
    for (T& slot : slots_) prepare(slot);
  }

  // Writer side: the slot to fill, then publish() hands it over.
  [[nodiscard]] T& write_slot() { return slots_[back_]; }
  void publish() {
    back_ = middle_.exchange(static_cast<std::uint8_t>(back_ | kFresh), std::memory_order_acq_rel) &
            kIndex;
  }

  // Reader side: takes the newest published slot if there is one; returns whether it changed.
  bool acquire() {
    if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    front_ = middle_.exchange(front_, std::memory_order_acq_rel) & kIndex;
    return true;
  }
  [[nodiscard]] const T& read_slot() const { return slots_[front_]; }

 private:
  static constexpr std::uint8_t kIndex = 0x3;
  static constexpr std::uint8_t kFresh = 0x4;
  std::array<T, 3> slots_{};
  std::uint8_t back_ = 0;
  std::uint8_t front_ = 1;
  std::atomic<std::uint8_t> middle_{2};
};

}  // namespace cathbox::session
