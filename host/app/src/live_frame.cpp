// The live frame a run sends to cathbox-server (host/server/include/server/live_schema.hpp):
// the snapshot's tools, tip, forces, contacts and named metrics, millimetres to 0.01 mm, and
// "fluoro": {"on": the pedal is down, "time_s": fluoroscopy time so far} when the case has one.
#include <algorithm>
#include <chrono>
#include <cmath>

#include <nlohmann/json.hpp>

#include "app/server_link.hpp"
#include "server/live_schema.hpp"
#include "session/metrics.hpp"

namespace cathbox::app {

using nlohmann::json;

namespace {

// A frame is read by people and drawn on screens, not replayed: 0.01 mm is plenty.
double mm(double v) { return std::round(v * 100.0) / 100.0; }
json vec(const glm::vec3& p) { return json::array({mm(p.x), mm(p.y), mm(p.z)}); }

std::int64_t unix_now_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace

std::string ServerLink::frame_json(const session::SceneSnapshot& snap, std::uint64_t seq,
                                   const std::vector<std::string>& tool_names) {
  json tools = json::array();
  for (int t = 0; t < snap.tool_count && t < static_cast<int>(server::kMaxToolsPerFrame); ++t) {
    const session::ToolView& v = snap.tools[static_cast<std::size_t>(t)];
    json nodes = json::array();
    // At most kMaxNodesPerTool nodes: every k-th, and always the tip.
    const std::size_t n = v.nodes_mm.size();
    const std::size_t step = (n + server::kMaxNodesPerTool - 1) / server::kMaxNodesPerTool;
    for (std::size_t i = 0; i < n; i += std::max<std::size_t>(step, 1)) {
      if (i + 1 < n || step <= 1) nodes.push_back(vec(v.nodes_mm[i]));
    }
    if (step > 1 && n > 0) nodes.push_back(vec(v.nodes_mm[n - 1]));
    const std::size_t ti = static_cast<std::size_t>(t);
    tools.push_back({{"name", ti < tool_names.size() ? tool_names[ti] : "tool" + std::to_string(t)}, {"active", v.active}, {"nodes_mm", std::move(nodes)}});
  }
  json contacts = json::array();
  for (const session::ContactView& c : snap.contacts) {
    if (contacts.size() < server::kMaxContactsPerFrame) contacts.push_back({{"p_mm", vec(c.point_mm)}, {"f_mN", mm(c.force_mN)}});
  }
  json metrics = json::object();
  for (const session::NamedMetric& m : session::named_metrics(snap.metrics)) {
    if (metrics.size() < server::kMaxMetricsPerFrame) metrics[m.name] = m.value;
  }
  json frame = {{"type", "frame"},
                {"seq", seq},
                {"t_ms", static_cast<double>(snap.sim_time_us) / 1000.0},
                {"tools", std::move(tools)},
                {"tip_mm", vec(snap.tip_mm)},
                {"forces", {{"hand_mN", mm(snap.hand_force_mN)}, {"wall_peak_mN", mm(snap.wall_force_mN)}}},
                {"contacts", std::move(contacts)},
                {"metrics", std::move(metrics)},
                {"sent_us", unix_now_us()}};
  if (snap.fluoro.available) {  // the fluoroscopy unit: the pedal (beam) and the time so far
    frame["fluoro"] = {{"on", snap.fluoro.image.beam_on}, {"time_s", snap.fluoro.exposure.fluoro_time_s}};
  }
  return frame.dump();
}

}  // namespace cathbox::app
