#include "tool/angioplasty.hpp"

#include <utility>

namespace cathbox::tool {

std::size_t first_balloon_tool(const Simulator& sim) {
  for (std::size_t t = 0; t < sim.tool_count(); ++t) {
    if (sim.balloon(t) != nullptr) return t;
  }
  return sim.tool_count();
}

Angioplasty::Angioplasty(vessel::VesselModel source, std::unique_ptr<WallModel> wall, WallSwap::Mode mode,
                         const LumenRemodelParams& params, WallBuilder builder, std::int64_t latency_ticks)
    : lumen_(std::move(source), params), swap_(std::move(wall), std::move(builder), mode, latency_ticks) {
  axis_.reserve(256);
}

void Angioplasty::after_step(Simulator& sim) {
  const auto now = static_cast<std::int64_t>(sim.steps());
  swap_.poll(sim, now);
  const std::size_t t = first_balloon_tool(sim);
  if (t < sim.tool_count()) {
    const Balloon& b = *sim.balloon(t);
    sim.balloon_axis(t, axis_);
    dirty_ |= lumen_.apply({axis_, b.diameter_mm(), b.inflated()});
  }
  // One wall at a time: a lumen that changed while one was being built asks again after it.
  if (dirty_ && !swap_.pending() && swap_.request(lumen_.take_model(), now)) dirty_ = false;
}

AngioplastyFigures Angioplasty::figures(const Simulator& sim) const {
  AngioplastyFigures f;
  f.lesion = lumen_.lesion().found();
  f.stenosis_before_percent = lumen_.stenosis_before_percent();
  f.residual_stenosis_percent = lumen_.stenosis_percent();
  f.reference_diameter_mm = lumen_.lesion().reference_diameter_mm;
  f.rupture_risk_events = lumen_.rupture_risk_events();
  f.max_oversize_ratio = lumen_.max_oversize_ratio();
  f.wall_swaps = swap_.swaps();
  f.swap_waits = swap_.waits();
  const std::size_t t = first_balloon_tool(sim);
  if (t < sim.tool_count()) {
    const Balloon& b = *sim.balloon(t);
    f.inflations = b.inflations();
    f.inflated_time_s = b.inflated_time_s();
    f.max_pressure_atm = b.max_pressure_atm();
    f.over_rated_burst = b.exceeded_rated_burst();
  }
  return f;
}

}  // namespace cathbox::tool
