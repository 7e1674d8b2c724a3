// POST /login, /logout, GET /me, POST /me/password, GET /users, POST /users, PATCH and DELETE
// /users/{name} (the last three audited)
#include "api_call.hpp"
#include "server/iso_time.hpp"
#include "server/json_input.hpp"
#include "server/user_delete.hpp"

namespace cathbox::server::api {

Reply login(Call& call) {
  Result<nlohmann::json> body = call.json_body();
  if (!body) return body.error();
  FieldReader f(body.value());
  const std::string name = f.string("name", 64);
  const std::string password = f.string("password", 256);
  f.only({"name", "password"});
  if (!f.ok()) return f.error();
  Result<LoginGrant> grant = call.c.auth.login(name, password, call.request.remote_address);
  if (!grant) return grant.error();
  return json_response(200, {{"token", grant.value().token},
                             {"expires_at", iso_time(grant.value().expires_us)},
                             {"user", user_json(grant.value().user)}});
}

Reply logout(Call& call) {
  call.c.auth.logout(call.caller);
  return no_content();
}

Reply me(Call& call) {
  const std::optional<User> u = call.c.store.user_by_id(call.caller.user_id);
  if (!u) return make_error(401, "authorization: account gone");
  return json_response(200, user_json(*u));
}

Reply change_password(Call& call) {
  Result<nlohmann::json> body = call.json_body();
  if (!body) return body.error();
  FieldReader f(body.value());
  const std::string old_password = f.string("old_password", 256);
  const std::string new_password = f.string("new_password", 256);
  f.only({"old_password", "new_password"});
  if (!f.ok()) return f.error();
  const std::optional<User> u = call.c.store.user_by_id(call.caller.user_id);
  if (!u) return make_error(401, "authorization: account gone");
  if (Status s = call.c.auth.verify_current_password(*u, old_password, call.request.remote_address); !s) return s.error();
  if (Status s = call.c.auth.set_password(u->id, new_password); !s) return s.error();
  return no_content();
}

Reply list_users(Call& call) {
  if (Status s = call.require_supervisor("listing users"); !s) return s.error();
  nlohmann::json users = nlohmann::json::array();
  for (const User& u : call.c.store.list_users()) users.push_back(user_json(u));
  return json_response(200, {{"users", std::move(users)}});
}

Reply create_user(Call& call) {
  if (Status s = call.require_admin("creating users"); !s) return s.error();
  Result<nlohmann::json> body = call.json_body();
  if (!body) return body.error();
  FieldReader f(body.value());
  const std::string name = f.string("name", 64);
  const std::string role_text = f.string("role", 16);
  const std::string password = f.string("password", 256);
  f.only({"name", "role", "password"});
  if (!f.ok()) return f.error();
  const std::optional<Role> role = parse_role(role_text);
  if (!role) return make_error(400, "field 'role': expected trainee, instructor or admin");
  Result<User> user = call.c.auth.create_user(name, *role, password);
  if (!user) return user.error();
  audit(call, "user.create", name, "role=" + role_text);
  ApiResponse r = json_response(201, user_json(user.value()));
  r.headers.emplace_back("Location", "/api/v1/users/" + name);
  return r;
}

Reply update_user(Call& call) {
  if (Status s = call.require_admin("changing users"); !s) return s.error();
  Result<nlohmann::json> body = call.json_body();
  if (!body) return body.error();
  FieldReader f(body.value());
  const std::optional<std::string> role_text = f.optional_string("role", 16);
  const std::optional<std::string> password = f.optional_string("password", 256);
  const std::optional<bool> disabled = f.optional_boolean("disabled");
  f.only({"role", "password", "disabled"});
  if (!f.ok()) return f.error();
  std::optional<Role> role;
  if (role_text) {
    role = parse_role(*role_text);
    if (!role) return make_error(400, "field 'role': expected trainee, instructor or admin");
  }
  const std::optional<User> u = call.c.store.user_by_name(call.params[0]);
  if (!u) return make_error(404, "no user '" + call.params[0] + "'");
  if (password) {
    if (const std::string bad = Auth::check_password(*password); !bad.empty()) return make_error(400, bad);
  }
  const Store::UserUpdate done = call.c.store.update_user_keeping_an_admin(u->id, role, std::nullopt, disabled, true);
  if (done == Store::UserUpdate::kLastAdmin) return make_error(409, "'" + u->name + "' is the last admin");
  if (done == Store::UserUpdate::kNotFound) return make_error(404, "no user '" + call.params[0] + "'");
  if (password) {
    if (Status s = call.c.auth.set_password(u->id, *password); !s) return s.error();
  }
  if (disabled.value_or(false)) call.c.store.delete_user_tokens(u->id);
  // Enabling an account is also its unlock: its login lockouts end.
  if (disabled && !*disabled) call.c.store.clear_account_login_failures(u->name);
  std::string detail;
  if (role_text) detail += "role=" + *role_text;
  if (disabled) detail += std::string(detail.empty() ? "" : " ") + (*disabled ? "disabled=true" : "disabled=false");
  if (password) detail += std::string(detail.empty() ? "" : " ") + "password";
  audit(call, "user.update", u->name, detail);
  return json_response(200, user_json(*call.c.store.user_by_id(u->id)));
}

// The account and all of its data (user_delete.hpp: one transaction, then the cached traces,
// its live streams and the database's leftovers), audited. Not oneself, not the last admin.
Reply delete_user(Call& call) {
  if (Status s = call.require_admin("deleting users"); !s) return s.error();
  if (call.params[0] == call.caller.name) return make_error(409, "'" + call.params[0] + "' is you: another admin deletes your account");
  Result<UserDeletion> done = delete_user_data(call.c.store, call.c.cache, &call.c.live, call.params[0], audit_entry(call));
  if (!done) return done.error();
  return no_content();
}

}  // namespace cathbox::server::api
