#include "session/event_log.hpp"

#include <algorithm>
#include <cstring>

namespace cathbox::session {

bool EventLog::push(std::int64_t time_us, const char* text) {
  const std::uint64_t head = head_.load(std::memory_order_relaxed);
  if (head - tail_.load(std::memory_order_acquire) >= kCapacity) {
    lost_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  LogEvent& e = ring_[head % kCapacity];
  e.time_us = time_us;
  const std::size_t n = std::min(std::strlen(text), e.text.size() - 1);
  std::memcpy(e.text.data(), text, n);
  e.text[n] = '\0';
  head_.store(head + 1, std::memory_order_release);
  return true;
}

bool EventLog::pop(LogEvent& out) {
  const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
  if (tail == head_.load(std::memory_order_acquire)) return false;
  out = ring_[tail % kCapacity];
  tail_.store(tail + 1, std::memory_order_release);
  return true;
}

}  // namespace cathbox::session
