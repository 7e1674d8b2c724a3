#include "server/role.hpp"

namespace cathbox::server {

std::string_view role_name(Role role) {
  switch (role) {
    case Role::kTrainee: return "trainee";
    case Role::kInstructor: return "instructor";
    case Role::kAdmin: return "admin";
  }
  return "trainee";
}

std::optional<Role> parse_role(std::string_view text) {
  if (text == "trainee") return Role::kTrainee;
  if (text == "instructor") return Role::kInstructor;
  if (text == "admin") return Role::kAdmin;
  return std::nullopt;
}

}  // namespace cathbox::server
