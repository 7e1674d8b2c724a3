#include "server/user_delete.hpp"

namespace cathbox::server {

Result<UserDeletion> delete_user_data(Store& store, ArtifactCache* cache, LiveService* live, const std::string& name, AuditEntry who) {
  const std::optional<User> u = store.user_by_name(name);
  if (!u) return make_error(404, "no user '" + name + "'");
  if (u->role == Role::kAdmin && !u->disabled && store.count_admins() <= 1) return make_error(409, "'" + u->name + "' is the last admin");
  const std::optional<std::vector<std::string>> records = store.delete_user(u->id);
  if (!records) return make_error(404, "no user '" + name + "'");
  UserDeletion done;
  done.results = static_cast<int>(records->size());
  if (cache != nullptr) {
    for (const std::string& hash : *records) cache->erase(trace_cache_key(hash));
  }
  if (live != nullptr) done.live_streams = live->forget_user(u->id);
  store.database().scrub();
  who.action = "user.delete";
  who.target = u->name;
  who.detail = "results=" + std::to_string(done.results);
  append_audit(store.database(), who);
  return done;
}

}  // namespace cathbox::server
