#pragma once
// A throwaway certificate authority for TLS tests and bench_server, made with the `openssl` command in a folder:
// an EC P-256 CA and server certificates it signs, valid, expired, or for another host.
#include <string>

#include "server/tls.hpp"

namespace cathbox::server::testing {

class TestCa {
 public:
  // Makes FOLDER/NAME.key and FOLDER/NAME.pem (self-signed, CN=NAME); throws when openssl fails.
  TestCa(std::string folder, std::string name);
  // A server certificate signed by this CA: subjectAltName `san` ("DNS:localhost,IP:127.0.0.1"),
  // valid from now for `days` (a negative count: already expired). FOLDER/LEAF.pem and .key.
  [[nodiscard]] TlsFiles issue(const std::string& leaf, const std::string& san, int days = 30) const;
  [[nodiscard]] const std::string& ca_file() const { return ca_pem_; }
  [[nodiscard]] const std::string& ca_key() const { return ca_key_; }

 private:
  std::string folder_, name_, ca_key_, ca_pem_;
};

}  // namespace cathbox::server::testing
