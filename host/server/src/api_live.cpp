// GET /live/rigs (the WebSocket endpoints are in http_server.cpp, over LiveService).
#include "api_call.hpp"

namespace cathbox::server::api {

Reply live_rigs(Call& call) {
  nlohmann::json m = call.c.live.rigs_message(call.caller);
  return json_response(200, {{"rigs", std::move(m["rigs"])}});
}

}  // namespace cathbox::server::api
