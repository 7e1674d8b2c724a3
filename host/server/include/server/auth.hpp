#pragma once
// Who is calling: logins (Argon2id), bearer tokens that expire, and login throttling.
//
// Tokens are 32 random bytes (43 characters, URL-safe base64); the store keeps only their
// SHA-256, so a copy of the database does not let anyone in. A token is good until
// AuthOptions::token_lifetime_us after the login, or until logout.
//
// Throttling, in virtual time through Clock:
//  - per account name and client address together, shared by every instance through the store:
//    after max_failures failed logins for that account from that address within
//    failure_window_us, further attempts from there are answered 429 without checking the
//    password until the window has moved past them. The owner, from another address, is not
//    locked out; a password reset (admin or `cathbox-server admin`) clears every lockout of the
//    account;
//  - per client address, in this process: a token bucket (address_burst attempts, refilled at
//    address_per_minute).
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>

#include "server/clock.hpp"
#include "server/password_hasher.hpp"
#include "server/result.hpp"
#include "server/store.hpp"

namespace cathbox::server {

struct Caller {
  std::int64_t user_id = 0;
  std::string name;
  Role role = Role::kTrainee;
  std::string token_hash;
};

struct AuthOptions {
  std::int64_t token_lifetime_us = 12LL * 3600 * 1'000'000;
  int max_failures = 5;
  std::int64_t failure_window_us = 15LL * 60 * 1'000'000;
  int address_burst = 20;
  double address_per_minute = 30.0;
};

struct LoginGrant {
  std::string token;
  std::int64_t expires_us = 0;
  User user;
};

class Auth {
 public:
  Auth(Store& store, Clock& clock, PasswordHasher hasher, AuthOptions options = {});

  // 401 for a wrong name or password (the same line for both), 429 when throttled.
  [[nodiscard]] Result<LoginGrant> login(const std::string& name, const std::string& password, const std::string& address);
  // `header` is the Authorization header ("Bearer TOKEN") or a bare token (WebSocket query).
  [[nodiscard]] Result<Caller> authenticate(std::string_view header);
  void logout(const Caller& caller);

  // Accounts (the admin endpoints and `cathbox-server admin`).
  [[nodiscard]] Result<User> create_user(const std::string& name, Role role, const std::string& password);
  [[nodiscard]] Status set_password(std::int64_t user_id, const std::string& password);
  // The account's current password, asked again before it is changed: wrong ones count as
  // failed logins (403), and a throttled account is answered 429 without checking.
  [[nodiscard]] Status verify_current_password(const User& user, const std::string& password, const std::string& address);
  [[nodiscard]] static std::string check_password(const std::string& password);

  [[nodiscard]] const AuthOptions& options() const { return options_; }
  [[nodiscard]] const PasswordHasher& hasher() const { return hasher_; }

 private:
  bool take_address_attempt(const std::string& address, std::int64_t now_us);
  // The account's throttle: the 429 when it has too many recent failures.
  [[nodiscard]] std::optional<Error> account_throttled(const std::string& key, std::int64_t now_us);
  // The store's login-failure key: "NAME@ADDRESS".
  [[nodiscard]] static std::string failure_key(const std::string& name, const std::string& address);

  Store& store_;
  Clock& clock_;
  PasswordHasher hasher_;
  AuthOptions options_;
  std::string dummy_hash_;  // verified against for unknown names, so both cost the same
  struct Bucket {
    double tokens = 0;
    std::int64_t updated_us = 0;
  };
  std::mutex buckets_mutex_;
  std::unordered_map<std::string, Bucket> buckets_;
};

}  // namespace cathbox::server
