#pragma once
// XXH3-64 over the bytes of plain values, in the order added: the project's one hasher (the
// session's state hashes, the collision tree's content hash, the fluoroscopy renderer's cache
// keys). Values are hashed as their object bytes: add only types without padding, or add
// their fields one by one.
#define XXH_STATIC_LINKING_ONLY  // XXH3_state_t on the stack
#include <xxhash.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace cathbox::base {

class XxhHasher {
 public:
  XxhHasher() { XXH3_64bits_reset(&state_); }
  void add_bytes(const void* data, std::size_t size) {
    if (size > 0) XXH3_64bits_update(&state_, data, size);
  }
  template <class T>
  void add(const T& value) {
    add_bytes(&value, sizeof value);
  }
  // The values' bytes, without their count.
  template <class T, std::size_t N>
  void add_span(std::span<T, N> values) {
    add_bytes(values.data(), values.size_bytes());
  }
  // The count, then the values' bytes.
  template <class T>
  void add_all(const std::vector<T>& values) {
    const std::uint64_t n = values.size();
    add(n);
    add_span(std::span<const T>(values));
  }
  [[nodiscard]] std::uint64_t digest() const { return XXH3_64bits_digest(&state_); }

 private:
  XXH3_state_t state_{};
};

}  // namespace cathbox::base
