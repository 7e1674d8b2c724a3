#include "server/password_hasher.hpp"

#include <argon2.h>
#include <openssl/rand.h>

#include <stdexcept>
#include <vector>

namespace cathbox::server {

std::string PasswordHasher::hash(const std::string& password) const {
  unsigned char salt[16];
  if (RAND_bytes(salt, sizeof salt) != 1) throw std::runtime_error("OpenSSL RAND_bytes failed");
  const std::size_t length =
      argon2_encodedlen(params_.time_cost, params_.memory_kib, params_.parallelism, sizeof salt, 32, Argon2_id);
  std::vector<char> encoded(length);
  const int rc = argon2id_hash_encoded(params_.time_cost, params_.memory_kib, params_.parallelism, password.data(), password.size(), salt,
                                       sizeof salt, 32, encoded.data(), encoded.size());
  if (rc != ARGON2_OK) throw std::runtime_error(std::string("argon2id: ") + argon2_error_message(rc));
  return std::string(encoded.data());
}

bool PasswordHasher::verify(const std::string& encoded, const std::string& password) const {
  if (encoded.rfind("$argon2id$", 0) != 0) return false;
  return argon2id_verify(encoded.c_str(), password.data(), password.size()) == ARGON2_OK;
}

}  // namespace cathbox::server
