#include "live_opening.hpp"

#include <charconv>

#include "http_fields.hpp"
#include "server/json_input.hpp"
#include "server/live_schema.hpp"

namespace cathbox::server {

namespace {

std::string query_value(const api::Target& t, const char* key) {
  const auto it = t.query.find(key);
  return it == t.query.end() ? std::string() : it->second;
}

// A rig's stream: query version (a number under a million) and assignment (an id) are checked
// before the stream is claimed.
void open_publisher(ApiContext& c, const Caller& who, const api::Target& t, LiveOpening& o) {
  const std::string version = query_value(t, "version");
  const std::string assignment = query_value(t, "assignment");
  std::int64_t v = 0, a = 0;
  const bool v_ok = version.empty() || (std::from_chars(version.data(), version.data() + version.size(), v).ec == std::errc() && v >= 0 && v < 1'000'000);
  const bool a_ok = assignment.empty() || (std::from_chars(assignment.data(), assignment.data() + assignment.size(), a).ec == std::errc() && a > 0);
  if (!v_ok || !a_ok) {
    o.refusal = error_response(make_error(400, !v_ok ? "query 'version': expected a number" : "query 'assignment': expected an id"));
    return;
  }
  Result<Publisher> started = c.live.start(who, t.segments[4], query_value(t, "case"), static_cast<int>(v),
                                           assignment.empty() ? std::nullopt : std::optional<std::int64_t>(a));
  if (!started) {
    o.refusal = error_response(started.error());
    return;
  }
  o.publisher = std::move(started.value());
  o.caller = who;
}

// A watcher: query rigs=a,b, checked as a watch message would be, and narrowed to what the
// caller may watch.
void open_watcher(ApiContext& c, const Caller& who, const api::Target& t, LiveOpening& o) {
  const std::string list = query_value(t, "rigs");
  nlohmann::json wanted = nlohmann::json::array();
  for (std::size_t at = 0; at < list.size();) {
    const std::size_t comma = std::min(list.find(',', at), list.size());
    if (comma > at) wanted.push_back(list.substr(at, comma - at));
    at = comma + 1;
  }
  Result<std::vector<std::string>> parsed_rigs = parse_watch_message(safe_dump(nlohmann::json{{"type", "watch"}, {"rigs", wanted}}));
  Result<std::vector<std::string>> ok = parsed_rigs ? c.live.allowed(who, parsed_rigs.value()) : parsed_rigs;
  if (!ok) {
    o.refusal = error_response(ok.error());
    return;
  }
  o.rigs = std::move(ok.value());
  o.caller = who;
  o.first_message = c.live.rigs_message(who).dump();
}

}  // namespace

LiveEndpoint live_endpoint(const api::Target& t) {
  const auto& seg = t.segments;
  if (seg.size() == 6 && seg[0] == "api" && seg[1] == "v1" && seg[2] == "live" && seg[3] == "rigs" && seg[5] == "stream") {
    return LiveEndpoint::kPublisher;
  }
  if (seg.size() == 4 && seg[0] == "api" && seg[1] == "v1" && seg[2] == "live" && seg[3] == "watch") return LiveEndpoint::kWatcher;
  return LiveEndpoint::kNone;
}

LiveOpening open_live(ApiContext& c, const api::Target& t, const std::string& token, LiveEndpoint endpoint) {
  LiveOpening o;
  try {
    Result<Caller> who = c.auth.authenticate(token);
    if (!who) {
      o.refusal = auth_refusal(who.error());
    } else if (endpoint == LiveEndpoint::kPublisher) {
      open_publisher(c, who.value(), t, o);
    } else {
      open_watcher(c, who.value(), t, o);
    }
  } catch (const StoreError& e) {
    o = LiveOpening{};
    o.refusal = error_response(make_error(503, std::string("database unavailable, retry: ") + e.what()));
  } catch (const std::exception& e) {
    o = LiveOpening{};
    o.refusal = error_response(make_error(500, std::string("internal error: ") + e.what()));
  }
  return o;
}

}  // namespace cathbox::server
