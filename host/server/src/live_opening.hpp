#pragma once
// What a WebSocket upgrade to /api/v1/live/... opens: which endpoint it names, and (asked of the
// store, on an API thread) who the caller is and what they may stream or watch.

#include <optional>
#include <string>
#include <vector>

#include "api_call.hpp"
#include "server/api.hpp"

namespace cathbox::server {

enum class LiveEndpoint { kNone, kPublisher, kWatcher };

// /api/v1/live/rigs/RIG/stream (a rig's stream) or /api/v1/live/watch (a watcher).
[[nodiscard]] LiveEndpoint live_endpoint(const api::Target& t);

// The caller (empty on a refusal, which `refusal` then says), a publisher's started stream, a
// watcher's allowed rigs and first message.
struct LiveOpening {
  ApiResponse refusal;
  std::optional<Caller> caller;
  std::optional<Publisher> publisher;
  std::vector<std::string> rigs;
  std::string first_message;
};

// Authenticates `token` and starts the stream (query version, assignment, case) or allows the
// watched rigs (query rigs=a,b). Asks the store: call it off the I/O threads.
[[nodiscard]] LiveOpening open_live(ApiContext& c, const api::Target& t, const std::string& token, LiveEndpoint endpoint);

}  // namespace cathbox::server
