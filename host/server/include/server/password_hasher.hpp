#pragma once
// Argon2id password hashes (Debian's libargon2), stored in the PHC string form
// "$argon2id$v=19$m=19456,t=2,p=1$salt$hash" so the parameters travel with each hash.
#include <cstdint>
#include <string>

namespace cathbox::server {

struct Argon2Params {
  std::uint32_t time_cost = 2;         // passes
  std::uint32_t memory_kib = 19 * 1024;  // 19 MiB (OWASP's minimum for Argon2id)
  std::uint32_t parallelism = 1;
};

class PasswordHasher {
 public:
  explicit PasswordHasher(Argon2Params params = {}) : params_(params) {}
  // A new random 16-byte salt per hash.
  [[nodiscard]] std::string hash(const std::string& password) const;
  // False for a wrong password and for anything that is not an Argon2id string.
  [[nodiscard]] bool verify(const std::string& encoded, const std::string& password) const;
  [[nodiscard]] const Argon2Params& params() const { return params_; }

 private:
  Argon2Params params_;
};

// Light parameters for tests and fuzzing only (t=1, 64 KiB): never for real accounts.
[[nodiscard]] inline Argon2Params test_argon2_params() { return Argon2Params{1, 64, 1}; }

}  // namespace cathbox::server
