#include "session/state_hash.hpp"

#define XXH_STATIC_LINKING_ONLY  // XXH3_state_t on the stack
#include <xxhash.h>

#include <cstring>

namespace cathbox::session {
namespace {

class Hasher {
 public:
  Hasher() { XXH3_64bits_reset(&state_); }
  template <class T>
  void add(const T& value) {
    XXH3_64bits_update(&state_, &value, sizeof value);
  }
  template <class T>
  void add_all(const std::vector<T>& values) {
    const std::uint64_t n = values.size();
    add(n);
    if (!values.empty()) XXH3_64bits_update(&state_, values.data(), values.size() * sizeof(T));
  }
  [[nodiscard]] std::uint64_t digest() { return XXH3_64bits_digest(&state_); }

 private:
  XXH3_state_t state_{};
};

}  // namespace

std::uint64_t state_hash(const tool::Snapshot& s) {
  Hasher h;
  const std::uint64_t tools = s.tools.size();
  h.add(tools);
  for (const tool::ToolSnapshot& t : s.tools) {
    h.add(t.insertion_mm);
    h.add(t.rotation_rad);
    h.add(t.hand_force_mN);
    h.add(t.hand_torque_mNmm);
    h.add(t.tip_segment);
    h.add_all(t.positions_mm);  // glm::dvec3: three doubles, no padding
    h.add_all(t.normals);
    const std::uint64_t contacts = t.contacts.size();
    h.add(contacts);
    for (const tool::RodContact& c : t.contacts) {
      const std::uint64_t node = c.node;
      h.add(node);
      h.add(c.normal_force_mN);
    }
  }
  return h.digest();
}

}  // namespace cathbox::session
