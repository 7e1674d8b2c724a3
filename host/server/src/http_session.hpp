#pragma once
// An HTTP connection (after any TLS handshake): its requests read under the limits, routed to the
// API, the static files or a WebSocket upgrade (ws_session.hpp), and answered.

#include <memory>

#include "connection_slots.hpp"
#include "http_server_impl.hpp"
#include "tls_or_plain_stream.hpp"

namespace cathbox::server {

// Serves `stream`: `address_slot` is the client address's share, taken when the connection was
// accepted (before any TLS handshake); `buffer` the bytes already read (the TLS detection's);
// `plain_on_tls_port`: answer 400 and close.
void start_http_session(HttpServer::Impl& s, std::unique_ptr<AddressSlot> address_slot, TlsOrPlainStream&& stream,
                        beast::flat_buffer&& buffer, bool plain_on_tls_port = false);

}  // namespace cathbox::server
