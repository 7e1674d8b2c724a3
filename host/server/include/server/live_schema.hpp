#pragma once
// The live stream's messages (JSON text over WebSocket). Documented in host/server/README.md.
//
// A rig (the trainer) opens  GET /api/v1/live/rigs/{rig}/stream?case=NAME[&version=N][&assignment=ID]
// and sends, ~30 times a second:
//   {"type": "frame", "seq": 812, "t_ms": 27066.0,
//    "tools": [{"name": "guidewire", "nodes_mm": [[x, y, z], ...]}],
//    "tip_mm": [x, y, z],
//    "forces": {"tip_mN": 41.2, "wall_peak_mN": 96.0, "hand_mN": 120.5},
//    "contacts": [{"p_mm": [x, y, z], "f_mN": 12.5}],
//    "fluoro": {"on": false, "time_s": 31.5},
//    "metrics": {"path_length_mm": 402.1, "wall_contacts": 3},
//    "sent_us": 1732467000123456}
// and {"type": "end"} when the run ends. Everything but type, seq and t_ms is optional.
//
// A watcher opens  GET /api/v1/live/watch[?rigs=a,b]  and receives
//   {"type": "rigs", "rigs": [{"rig": ..., "user": ..., "case": ..., ...}]}   at once
//   {"type": "started", "rig": {...}} / {"type": "ended", "rig": "rig-07"}   (supervisors)
//   {"type": "frame", "rig": "rig-07", "server_us": ..., "frame": {...as sent...}}
// and may send {"type": "watch", "rigs": ["rig-07", ...]} to change what it watches.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/result.hpp"

namespace cathbox::server {

inline constexpr std::size_t kMaxFrameBytes = 256 * 1024;
inline constexpr std::size_t kMaxWatcherMessageBytes = 4096;
inline constexpr std::size_t kMaxToolsPerFrame = 8;
inline constexpr std::size_t kMaxNodesPerTool = 1024;
inline constexpr std::size_t kMaxContactsPerFrame = 256;
inline constexpr std::size_t kMaxMetricsPerFrame = 64;
inline constexpr std::size_t kMaxWatchedRigs = 64;

enum class PublisherMessage { kFrame, kEnd };

struct ParsedPublisherMessage {
  PublisherMessage kind = PublisherMessage::kFrame;
  nlohmann::json frame;  // the validated frame (kFrame)
};

// Validates one message from a rig; 400 "frame: field 'tools[0].nodes_mm[3]': ..." on error.
[[nodiscard]] Result<ParsedPublisherMessage> parse_publisher_message(std::string_view text);

// What a watcher asks for: the rigs to watch (replacing the previous set).
[[nodiscard]] Result<std::vector<std::string>> parse_watch_message(std::string_view text);

// The text a watcher receives for one frame (built once per frame, shared by every watcher).
[[nodiscard]] std::string frame_envelope(const std::string& rig, std::int64_t server_us, const nlohmann::json& frame);

}  // namespace cathbox::server
