#pragma once
// SHA-256 (OpenSSL) and random bytes, for content hashes, token hashes and tokens.
#include <string>
#include <string_view>

namespace cathbox::server {

// Lower-case hex digest of `bytes` (64 characters).
[[nodiscard]] std::string sha256_hex(std::string_view bytes);
// `count` bytes from the operating system's CSPRNG, as URL-safe base64 without padding.
[[nodiscard]] std::string random_token(int count = 32);

}  // namespace cathbox::server
