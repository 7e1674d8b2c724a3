#include "tls_server_context.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <utility>

#include <openssl/err.h>
#include <openssl/ssl.h>

namespace cathbox::server {

namespace ssl = boost::asio::ssl;

namespace {

// TLS 1.2 suites with forward secrecy and authenticated encryption (TLS 1.3's own five are all so).
constexpr const char* kTls12Ciphers =
    "ECDHE-ECDSA-AES128-GCM-SHA256:ECDHE-RSA-AES128-GCM-SHA256:ECDHE-ECDSA-AES256-GCM-SHA384:"
    "ECDHE-RSA-AES256-GCM-SHA384:ECDHE-ECDSA-CHACHA20-POLY1305:ECDHE-RSA-CHACHA20-POLY1305";

std::string openssl_reason(const boost::system::error_code& ec) {
  const unsigned long e = ERR_get_error();
  ERR_clear_error();
  if (e != 0) {
    const char* reason = ERR_reason_error_string(e);
    if (reason != nullptr) return reason;
  }
  return ec.message();
}

}  // namespace

Result<std::shared_ptr<ssl::context>> make_server_tls_context(const TlsFiles& files) {
  auto ctx = std::make_shared<ssl::context>(ssl::context::tls_server);
  SSL_CTX* native = ctx->native_handle();
  SSL_CTX_set_min_proto_version(native, TLS1_2_VERSION);
  SSL_CTX_set_options(native, SSL_OP_NO_COMPRESSION | SSL_OP_NO_RENEGOTIATION | SSL_OP_CIPHER_SERVER_PREFERENCE);
  if (SSL_CTX_set_cipher_list(native, kTls12Ciphers) != 1) return make_error(500, "TLS: this OpenSSL has none of the TLS 1.2 suites");
  ERR_clear_error();
  for (const auto& [option, file] : {std::pair{"--tls-cert ", &files.cert_file}, std::pair{"--tls-key ", &files.key_file}}) {
    errno = 0;
    if (std::FILE* f = std::fopen(file->c_str(), "rb"); f != nullptr) {
      std::fclose(f);
    } else {
      return make_error(400, option + *file + ": cannot read: " + std::strerror(errno));
    }
  }
  boost::system::error_code ec;
  ctx->use_certificate_chain_file(files.cert_file, ec);
  if (ec) return make_error(400, "--tls-cert " + files.cert_file + ": " + openssl_reason(ec));
  ctx->use_private_key_file(files.key_file, ssl::context::pem, ec);
  if (ec) {
    std::string why = openssl_reason(ec);
    if (why.find("mismatch") != std::string::npos) why = "does not match the certificate in " + files.cert_file;
    return make_error(400, "--tls-key " + files.key_file + ": " + why);
  }
  if (SSL_CTX_check_private_key(native) != 1) {
    ERR_clear_error();
    return make_error(400, "--tls-key " + files.key_file + ": does not match the certificate in " + files.cert_file);
  }
  return ctx;
}

}  // namespace cathbox::server
