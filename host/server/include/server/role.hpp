#pragma once
// The three roles of a training centre. What each may do is decided on the server, per
// endpoint (each handler checks its caller: Call::require_* in src/api.cpp); the table is in
// host/server/README.md.
#include <optional>
#include <string_view>

namespace cathbox::server {

enum class Role { kTrainee = 0, kInstructor = 1, kAdmin = 2 };

[[nodiscard]] std::string_view role_name(Role role);
[[nodiscard]] std::optional<Role> parse_role(std::string_view text);
// Instructors and admins see every trainee's work and every rig.
[[nodiscard]] inline bool can_supervise(Role role) { return role != Role::kTrainee; }

}  // namespace cathbox::server
