#include "session/state_hash.hpp"

#include <cstring>

#include "base/xxh_hasher.hpp"

namespace cathbox::session {

std::uint64_t state_hash(const tool::Snapshot& s) {
  base::XxhHasher h;
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
