#include "server/auth.hpp"

#include <algorithm>

#include "server/json_input.hpp"
#include "server/sha256.hpp"

namespace cathbox::server {

Auth::Auth(Store& store, Clock& clock, PasswordHasher hasher, AuthOptions options)
    : store_(store), clock_(clock), hasher_(hasher), options_(options), dummy_hash_(hasher_.hash(random_token(12))) {}

bool Auth::take_address_attempt(const std::string& address, std::int64_t now_us) {
  std::lock_guard lock(buckets_mutex_);
  if (buckets_.size() > 100'000) buckets_.clear();  // bounded memory under a flood of addresses
  auto [it, fresh] = buckets_.try_emplace(address, Bucket{static_cast<double>(options_.address_burst), now_us});
  Bucket& b = it->second;
  const double refill = static_cast<double>(now_us - b.updated_us) / 60e6 * options_.address_per_minute;
  b.tokens = std::min(static_cast<double>(options_.address_burst), b.tokens + std::max(0.0, refill));
  b.updated_us = now_us;
  if (b.tokens < 1.0) return false;
  b.tokens -= 1.0;
  return true;
}

std::string Auth::failure_key(const std::string& name, const std::string& address) { return name + "@" + address; }

std::optional<Error> Auth::account_throttled(const std::string& key, std::int64_t now_us) {
  if (store_.login_failures_since(key, now_us - options_.failure_window_us) < options_.max_failures) return std::nullopt;
  Error e = make_error(429, "login: too many failed attempts for this account; try again in " +
                                std::to_string(options_.failure_window_us / 60'000'000) + " minutes");
  e.retry_after_s = static_cast<int>(options_.failure_window_us / 1'000'000);
  return e;
}

Status Auth::verify_current_password(const User& user, const std::string& password, const std::string& address) {
  const std::int64_t now = clock_.now_us();
  const std::string key = failure_key(user.name, address);
  if (std::optional<Error> throttled = account_throttled(key, now)) return *throttled;
  if (!hasher_.verify(user.password_hash, password)) {
    store_.record_login_failure(key, now);
    return make_error(403, "field 'old_password': wrong password");
  }
  return Ok{};
}

Result<LoginGrant> Auth::login(const std::string& name, const std::string& password, const std::string& address) {
  const std::int64_t now = clock_.now_us();
  if (!take_address_attempt(address, now)) {
    return make_error(429, "login: too many attempts from " + address + "; wait a minute");
  }
  // Failures count per account and address together: guessing from one address does not lock
  // the owner out from theirs.
  const std::string key = failure_key(name, address);
  if (std::optional<Error> throttled = account_throttled(key, now)) return *throttled;
  const std::optional<User> user = store_.user_by_name(name);
  const bool good = user ? hasher_.verify(user->password_hash, password) : (void(hasher_.verify(dummy_hash_, password)), false);
  if (!good || user->disabled) {
    store_.record_login_failure(key, now);
    return make_error(401, "login: wrong user name or password");
  }
  store_.clear_login_failures(key);
  LoginGrant grant;
  grant.token = random_token(32);
  grant.expires_us = now + options_.token_lifetime_us;
  grant.user = *user;
  store_.insert_token(sha256_hex(grant.token), user->id, now, grant.expires_us);
  return grant;
}

Result<Caller> Auth::authenticate(std::string_view header) {
  std::string_view token = header;
  if (token.rfind("Bearer ", 0) == 0 || token.rfind("bearer ", 0) == 0) token.remove_prefix(7);
  while (!token.empty() && token.front() == ' ') token.remove_prefix(1);
  if (token.empty()) return make_error(401, "authorization: missing bearer token (log in at POST /api/v1/login)");
  if (token.size() > 128) return make_error(401, "authorization: malformed token");
  const std::string hash = sha256_hex(token);
  const std::optional<TokenOwner> owner = store_.token_owner(hash);
  if (!owner) return make_error(401, "authorization: unknown token (log in again)");
  if (owner->expires_us <= clock_.now_us()) return make_error(401, "authorization: token expired (log in again)");
  if (owner->user.disabled) return make_error(401, "authorization: account disabled");
  return Caller{owner->user.id, owner->user.name, owner->user.role, hash};
}

void Auth::logout(const Caller& caller) { store_.delete_token(caller.token_hash); }

std::string Auth::check_password(const std::string& password) {
  if (password.size() < 8) return "password: at least 8 characters";
  if (password.size() > 256) return "password: at most 256 characters";
  return {};
}

Result<User> Auth::create_user(const std::string& name, Role role, const std::string& password) {
  if (const std::string bad = check_user_name(name); !bad.empty()) return make_error(400, bad);
  if (const std::string bad = check_password(password); !bad.empty()) return make_error(400, bad);
  std::optional<User> user = store_.create_user(name, role, hasher_.hash(password), clock_.now_us());
  if (!user) return make_error(409, "user '" + name + "' already exists");
  return *user;
}

Status Auth::set_password(std::int64_t user_id, const std::string& password) {
  if (const std::string bad = check_password(password); !bad.empty()) return make_error(400, bad);
  if (!store_.update_user(user_id, std::nullopt, hasher_.hash(password), std::nullopt)) return make_error(404, "no such user");
  store_.delete_user_tokens(user_id);
  // A reset lifts every lockout of the account.
  if (const std::optional<User> u = store_.user_by_id(user_id)) store_.clear_account_login_failures(u->name);
  return Ok{};
}

}  // namespace cathbox::server
