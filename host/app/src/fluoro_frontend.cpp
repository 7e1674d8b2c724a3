#include "app/fluoro_frontend.hpp"

#include <algorithm>
#include <cmath>

namespace cathbox::app {

FluoroInputs fluoro_inputs_from_snapshot(const session::SceneSnapshot& snapshot, const SnapshotFluoroSettings& settings) {
  FluoroInputs in;
  in.pose = settings.pose;
  in.patient_transmission = settings.patient_transmission;
  // Pedal held since the run started: pulse k at k / rate seconds; the image shows the last.
  const auto pulse = static_cast<std::int64_t>(std::floor(static_cast<double>(snapshot.sim_time_us) * 1e-6 * settings.pulse_rate_hz));
  in.image.pulse = pulse;
  in.image.pulse_time_us = std::llround(static_cast<double>(pulse) * 1e6 / settings.pulse_rate_hz);
  in.image.beam_on = true;
  in.shown.pulse = pulse;
  const int tools = std::min(snapshot.tool_count, session::SceneSnapshot::kMaxTools);
  for (int i = 0; i < tools; ++i) {
    const session::ToolView& view = snapshot.tools[static_cast<std::size_t>(i)];
    FluoroTool tool;
    tool.nodes_mm = view.nodes_mm;
    tool.radius_mm = view.radius_mm;
    tool.markers.push_back({0.0, settings.tip_marker_mm, flow::XrayMaterial::kPlatinum});
    in.shown.tools.push_back(std::move(tool));
  }
  return in;
}

}  // namespace cathbox::app
