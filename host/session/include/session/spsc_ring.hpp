#pragma once
// A bounded single-producer single-consumer ring of values: push() on one thread, pop() on
// another, neither ever waits nor allocates. The recorder passes its block buffers between the
// haptic thread and the writer thread with two of these.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace cathbox::session {

template <class T, std::size_t N>
class SpscRing {
 public:
  // Producer. False when full.
  bool push(const T& value) {
    const std::uint64_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) >= N) return false;
    ring_[head % N] = value;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }
  // Consumer. False when empty.
  bool pop(T& out) {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    out = ring_[tail % N];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }
  [[nodiscard]] bool empty() const {
    return head_.load(std::memory_order_acquire) == tail_.load(std::memory_order_acquire);
  }

 private:
  std::array<T, N> ring_{};
  std::atomic<std::uint64_t> head_{0};
  std::atomic<std::uint64_t> tail_{0};
};

}  // namespace cathbox::session
