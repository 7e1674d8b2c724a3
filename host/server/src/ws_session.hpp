#pragma once
// A live WebSocket (a rig's stream or a watcher), opened once the upgrade was authenticated and
// allowed: its messages in and out, its queue, its idle eviction and token rechecks.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "connection_slots.hpp"
#include "http_server_impl.hpp"
#include "tls_or_plain_stream.hpp"

namespace cathbox::server {

// Accepts the upgrade `req` on `stream`; the socket then lives as long as its peer keeps it.
void start_ws_session(HttpServer::Impl& s, std::unique_ptr<AddressSlot> address_slot, std::unique_ptr<AccountSlot> account_slot,
                      TlsOrPlainStream&& stream, Caller caller, std::optional<Publisher> publisher, std::vector<std::string> watching,
                      std::string first_message, http::request<http::string_body> req);

}  // namespace cathbox::server
