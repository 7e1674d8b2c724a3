#pragma once
// The server's TLS context from its certificate and key files (see server/tls.hpp).
#include <memory>

#include <boost/asio/ssl/context.hpp>

#include "server/result.hpp"
#include "server/tls.hpp"

namespace cathbox::server {

// 400 with the file and the reason when a file is missing, unreadable, or the key does not match.
[[nodiscard]] Result<std::shared_ptr<boost::asio::ssl::context>> make_server_tls_context(const TlsFiles& files);

}  // namespace cathbox::server
