#pragma once
// The client side of TLS (see server/tls.hpp): one shared context per CA file, the host name
// check, and the one line that says why a handshake failed.
#include <memory>
#include <string>

#include <boost/asio/ssl/context.hpp>

#include "server/result.hpp"
#include "tls_or_plain_stream.hpp"

namespace cathbox::server {

// The context for client_ca_file() (built once per file, then shared); 400 when the file cannot
// be loaded.
[[nodiscard]] Result<std::shared_ptr<boost::asio::ssl::context>> client_tls_context();
// Before the handshake: send `host` as SNI (names only) and require the certificate to name it.
void expect_server_name(TlsOrPlainStream::TlsStream& stream, const std::string& host);
// "TLS to HOST:PORT: <why>" for a failed handshake, naming the certificate problem when there is one.
[[nodiscard]] std::string tls_failure_line(TlsOrPlainStream::TlsStream& stream, const boost::system::error_code& ec,
                                           const std::string& host, const std::string& port);

}  // namespace cathbox::server
