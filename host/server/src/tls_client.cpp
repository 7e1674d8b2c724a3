#include "tls_client.hpp"

#include <map>
#include <mutex>

#include <boost/asio/ip/address.hpp>
#include <openssl/err.h>
#include <openssl/ssl.h>
#include <openssl/x509v3.h>

#include "server/tls.hpp"

namespace cathbox::server {

namespace ssl = boost::asio::ssl;

namespace {

std::mutex g_mutex;
std::string g_ca_file;
std::map<std::string, std::shared_ptr<ssl::context>> g_contexts;

}  // namespace

void set_client_ca_file(std::string pem_path) {
  std::lock_guard lock(g_mutex);
  g_ca_file = std::move(pem_path);
}

std::string client_ca_file() {
  std::lock_guard lock(g_mutex);
  return g_ca_file;
}

Result<std::shared_ptr<ssl::context>> client_tls_context() {
  std::lock_guard lock(g_mutex);
  if (auto it = g_contexts.find(g_ca_file); it != g_contexts.end()) return it->second;
  auto ctx = std::make_shared<ssl::context>(ssl::context::tls_client);
  SSL_CTX_set_min_proto_version(ctx->native_handle(), TLS1_2_VERSION);
  ctx->set_verify_mode(ssl::verify_peer);
  boost::system::error_code ec;
  if (g_ca_file.empty()) {
    ctx->set_default_verify_paths(ec);
    if (ec) return make_error(400, "TLS: the system trust store cannot be read: " + ec.message());
  } else {
    ctx->load_verify_file(g_ca_file, ec);
    if (ec) {
      ERR_clear_error();
      return make_error(400, "--ca-file " + g_ca_file + ": not a readable PEM certificate file");
    }
  }
  g_contexts.emplace(g_ca_file, ctx);
  return ctx;
}

void expect_server_name(TlsOrPlainStream::TlsStream& stream, const std::string& host) {
  SSL* native = stream.native_handle();
  boost::system::error_code ec;
  (void)boost::asio::ip::make_address(host, ec);
  if (ec) {
    SSL_set_tlsext_host_name(native, host.c_str());
    SSL_set1_host(native, host.c_str());
  } else {
    X509_VERIFY_PARAM_set1_ip_asc(SSL_get0_param(native), host.c_str());
  }
}

std::string tls_failure_line(TlsOrPlainStream::TlsStream& stream, const boost::system::error_code& ec, const std::string& host,
                             const std::string& port) {
  const std::string where = "TLS to " + host + ":" + port + ": ";
  ERR_clear_error();
  const long verify = SSL_get_verify_result(stream.native_handle());
  if (verify != X509_V_OK) {
    const std::string trust = client_ca_file().empty() ? "the system trust store" : "--ca-file " + client_ca_file();
    return where + "certificate verify failed: " + X509_verify_cert_error_string(verify) + " (trusting " + trust + ")";
  }
  std::string why = ec.message();
  if (ec == ssl::error::stream_truncated || ec == boost::asio::error::eof) why = "the server closed the connection (is it HTTPS?)";
  if (why.find("wrong version number") != std::string::npos) why += " (the server speaks plain HTTP: use http://)";
  return where + why;
}

}  // namespace cathbox::server
