#pragma once
// XXH3-64 over the bytes of plain values, in the order added: the session's state hashes
// (state_hash.cpp, and the fluoroscopy unit's part of them). Private to host/session.
#define XXH_STATIC_LINKING_ONLY  // XXH3_state_t on the stack
#include <xxhash.h>

#include <cstdint>
#include <vector>

namespace cathbox::session {

class XxhHasher {
 public:
  XxhHasher() { XXH3_64bits_reset(&state_); }
  template <class T>
  void add(const T& value) {
    XXH3_64bits_update(&state_, &value, sizeof value);
  }
  // The count, then the values' bytes.
  template <class T>
  void add_all(const std::vector<T>& values) {
    const std::uint64_t n = values.size();
    add(n);
    if (!values.empty()) XXH3_64bits_update(&state_, values.data(), values.size() * sizeof(T));
  }
  [[nodiscard]] std::uint64_t digest() const { return XXH3_64bits_digest(&state_); }

 private:
  XXH3_state_t state_{};
};

}  // namespace cathbox::session
