#include "server/live_schema.hpp"

#include <cmath>
#include <optional>

#include "server/json_input.hpp"

namespace cathbox::server {

namespace {

// Checks `v` is [x, y, z] of finite numbers; empty string when fine.
std::string check_vec3(const nlohmann::json& v) {
  if (!v.is_array() || v.size() != 3) return "expected [x, y, z]";
  for (const auto& x : v) {
    if (!x.is_number() || !std::isfinite(x.get<double>())) return "expected [x, y, z] of finite numbers";
  }
  return {};
}

std::string check_number(const nlohmann::json& v) {
  return v.is_number() && std::isfinite(v.get<double>()) ? std::string() : std::string("expected a finite number");
}

Error frame_error(const std::string& where, const std::string& what) { return make_error(400, "frame: field '" + where + "': " + what); }

// Each check below: the frame's field (when present) as watchers draw it, or what is wrong.

std::optional<Error> check_tool(const nlohmann::json& tool, const std::string& at) {
  if (!tool.is_object()) return frame_error(at, "expected an object");
  for (const auto& [key, value] : tool.items()) {
    if (key != "name" && key != "active" && key != "nodes_mm") return frame_error(at + "." + key.substr(0, 64), "unknown field");
    if (key == "active" && !value.is_boolean()) return frame_error(at + ".active", "expected true or false");
  }
  const auto name = tool.find("name");
  if (name == tool.end() || !name->is_string() || name->get_ref<const std::string&>().size() > 64) {
    return frame_error(at + ".name", "expected a string of at most 64 bytes");
  }
  const auto nodes = tool.find("nodes_mm");
  if (nodes == tool.end() || !nodes->is_array() || nodes->size() > kMaxNodesPerTool) {
    return frame_error(at + ".nodes_mm", "expected an array of at most " + std::to_string(kMaxNodesPerTool) + " points");
  }
  for (std::size_t n = 0; n < nodes->size(); ++n) {
    if (const std::string bad = check_vec3((*nodes)[n]); !bad.empty()) return frame_error(at + ".nodes_mm[" + std::to_string(n) + "]", bad);
  }
  return std::nullopt;
}

// The frame's array `key` (when present): at most `max` entries, each passing `check_entry`
// (entry, "key[i]").
template <class CheckEntry>
std::optional<Error> check_array(const nlohmann::json& frame, const std::string& key, std::size_t max, const char* what,
                                 CheckEntry check_entry) {
  const auto it = frame.find(key);
  if (it == frame.end()) return std::nullopt;
  if (!it->is_array() || it->size() > max) {
    return frame_error(key, "expected an array of at most " + std::to_string(max) + " " + what);
  }
  for (std::size_t i = 0; i < it->size(); ++i) {
    if (std::optional<Error> e = check_entry((*it)[i], key + "[" + std::to_string(i) + "]")) return e;
  }
  return std::nullopt;
}

std::optional<Error> check_tools(const nlohmann::json& frame) {
  return check_array(frame, "tools", kMaxToolsPerFrame, "tools", check_tool);
}

// "forces" and "metrics": named numbers (or booleans).
std::optional<Error> check_number_groups(const nlohmann::json& frame) {
  for (const char* group : {"forces", "metrics"}) {
    const auto it = frame.find(group);
    if (it == frame.end()) continue;
    if (!it->is_object() || it->size() > kMaxMetricsPerFrame) {
      return frame_error(group, "expected an object of at most " + std::to_string(kMaxMetricsPerFrame) + " numbers");
    }
    for (const auto& [key, value] : it->items()) {
      if (key.size() > 64) return frame_error(group, "a name is longer than 64 bytes");
      if (const std::string bad = check_number(value); !bad.empty() && !value.is_boolean()) {
        return frame_error(std::string(group) + "." + key, bad);
      }
    }
  }
  return std::nullopt;
}

std::optional<Error> check_contact(const nlohmann::json& contact, const std::string& at) {
  if (!contact.is_object() || contact.size() > 2) return frame_error(at, "expected an object {p_mm, f_mN}");
  const auto p = contact.find("p_mm");
  if (p == contact.end()) return frame_error(at + ".p_mm", "missing");
  if (const std::string bad = check_vec3(*p); !bad.empty()) return frame_error(at + ".p_mm", bad);
  const auto force = contact.find("f_mN");
  if (force == contact.end()) return frame_error(at + ".f_mN", "missing");
  if (const std::string bad = check_number(*force); !bad.empty()) return frame_error(at + ".f_mN", bad);
  return std::nullopt;
}

std::optional<Error> check_contacts(const nlohmann::json& frame) {
  return check_array(frame, "contacts", kMaxContactsPerFrame, "contacts", check_contact);
}

std::optional<Error> check_fluoro(const nlohmann::json& frame) {
  if (const auto it = frame.find("fluoro"); it != frame.end()) {
    if (!it->is_object() || it->size() > 16) return frame_error("fluoro", "expected an object");
    for (const auto& [key, value] : it->items()) {
      if (!value.is_boolean() && !check_number(value).empty()) return frame_error("fluoro." + key.substr(0, 64), "expected a number or boolean");
    }
  }
  return std::nullopt;
}

Result<nlohmann::json> check_frame(nlohmann::json frame) {
  FieldReader f(frame);
  (void)f.integer("seq", 0, INT64_MAX);
  (void)f.number("t_ms");
  (void)f.optional_integer("sent_us", 0, INT64_MAX);
  // Only the fields watchers draw are forwarded: anything else is refused, not relayed.
  f.only({"seq", "t_ms", "sent_us", "tools", "tip_mm", "forces", "metrics", "contacts", "fluoro"});
  if (!f.ok()) return make_error(400, "frame: " + f.error().message);
  // The first problem in the order tools, tip, forces/metrics, contacts, fluoro.
  if (std::optional<Error> e = check_tools(frame)) return *e;
  if (const auto it = frame.find("tip_mm"); it != frame.end()) {
    if (const std::string bad = check_vec3(*it); !bad.empty()) return frame_error("tip_mm", bad);
  }
  if (std::optional<Error> e = check_number_groups(frame)) return *e;
  if (std::optional<Error> e = check_contacts(frame)) return *e;
  if (std::optional<Error> e = check_fluoro(frame)) return *e;
  return frame;
}

}  // namespace

Result<ParsedPublisherMessage> parse_publisher_message(std::string_view text) {
  if (text.size() > kMaxFrameBytes) {
    return make_error(413, "frame: " + std::to_string(text.size()) + " bytes is over the limit of " + std::to_string(kMaxFrameBytes));
  }
  Result<nlohmann::json> parsed = parse_json_object(text, "frame");
  if (!parsed) return parsed.error();
  const auto type = parsed.value().find("type");
  if (type == parsed.value().end() || !type->is_string()) return make_error(400, "frame: field 'type': missing");
  ParsedPublisherMessage out;
  if (*type == "end") {
    out.kind = PublisherMessage::kEnd;
    return out;
  }
  if (*type != "frame") return make_error(400, "frame: field 'type': expected \"frame\" or \"end\"");
  parsed.value().erase("type");
  Result<nlohmann::json> frame = check_frame(std::move(parsed.value()));
  if (!frame) return frame.error();
  out.frame = std::move(frame.value());
  return out;
}

Result<std::vector<std::string>> parse_watch_message(std::string_view text) {
  if (text.size() > kMaxWatcherMessageBytes) return make_error(413, "message: over " + std::to_string(kMaxWatcherMessageBytes) + " bytes");
  Result<nlohmann::json> parsed = parse_json_object(text, "message");
  if (!parsed) return parsed.error();
  FieldReader f(parsed.value());
  if (f.string("type", 16) != "watch" && f.ok()) f.fail("type", "expected \"watch\"");
  const nlohmann::json& rigs = f.array("rigs");
  f.only({"type", "rigs"});
  if (!f.ok()) return f.error();
  if (rigs.size() > kMaxWatchedRigs) return make_error(400, "field 'rigs': at most " + std::to_string(kMaxWatchedRigs) + " rigs");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < rigs.size(); ++i) {
    if (!rigs[i].is_string()) return make_error(400, "field 'rigs[" + std::to_string(i) + "]': expected a string");
    const std::string& rig = rigs[i].get_ref<const std::string&>();
    if (const std::string bad = check_slug(rig); !bad.empty()) return make_error(400, "field 'rigs[" + std::to_string(i) + "]': " + bad);
    out.push_back(rig);
  }
  return out;
}

std::string frame_envelope(const std::string& rig, std::int64_t server_us, const nlohmann::json& frame) {
  std::string out = R"({"type":"frame","rig":)";
  out += nlohmann::json(rig).dump();
  out += R"(,"server_us":)";
  out += std::to_string(server_us);
  out += R"(,"frame":)";
  out += frame.dump();
  out += '}';
  return out;
}

}  // namespace cathbox::server
