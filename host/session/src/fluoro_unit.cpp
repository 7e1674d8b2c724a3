#include "session/fluoro_unit.hpp"

#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "session/event_log.hpp"
#include "session/fluoro_controls.hpp"
#include "tool/simulator.hpp"
#include "base/xxh_hasher.hpp"

namespace cathbox::session {
namespace {

constexpr double kTipOutsideMarginMm = 1.0;  // a tip this far beyond the lumen radius is not in a vessel

}  // namespace

FluoroUnit::FluoroUnit(const flow::FlowNetwork& network, const std::vector<tool::ToolSpec>& tools,
                       const tool::Snapshot& snapshot, std::size_t max_nodes_per_tool, const flow::CArmPose& pose)
    : network_(network),
      tools_(tools),
      snap_(snapshot),
      transport_(network),
      scope_(flow::HeadPhantom::neuro(), pose),
      field_(transport_) {
  transport_step_us_ = std::llround(transport_.options().step_s * 1e6);
  const std::size_t segments = network.model().segments.size();
  for (std::uint32_t s = 0; s < segments; ++s) {
    const std::span<const double> b = transport_.cell_bounds_mm(s);
    for (std::size_t j = 0; j + 1 < b.size(); ++j) {
      const double mid = 0.5 * (b[j] + b[j + 1]);
      cells_.push_back({s, static_cast<float>(b[j]), static_cast<float>(b[j + 1]),
                        glm::vec3(transport_.locator().point_at(s, mid)),
                        static_cast<float>(transport_.locator().radius_at(s, mid))});
    }
  }
  for (std::vector<float>* v : {&shown_, &previous_, &run_mask_, &peak_, &peak_mask_, &roadmap_, &roadmap_mask_}) {
    v->assign(cells_.size(), 0.0F);
  }
  for (std::vector<glm::vec3>& n : pulse_nodes_) n.reserve(max_nodes_per_tool);
  for (std::vector<glm::vec3>& n : pulse_coil_nodes_) n.reserve(max_nodes_per_tool);
}

void FluoroUnit::log(ControlContext& ctx, const char* fmt, ...) {
  char buf[112];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  (void)ctx.events.push(ctx.time_us, buf);
}

bool FluoroUnit::apply(Control& c, ControlContext& ctx) {
  bool applied = false;
  bool decoded = true;  // the payload has its kind's size and finite values
  switch (static_cast<ControlKind>(c.kind)) {
    case ControlKind::kFluoroPedal:
      if (const auto on = fluoro_control::read_flag(c)) {
        scope_.set_pedal(*on);
        applied = true;
      } else {
        decoded = false;
      }
      break;
    case ControlKind::kInject:
      if (const auto p = fluoro_control::read_inject(c)) {
        applied = inject(*p, ctx);
      } else {
        decoded = false;
      }
      break;
    case ControlKind::kCArmAngles:
      if (const auto a = fluoro_control::read_angles(c)) {
        flow::CArmPose pose = scope_.carm().pose();
        pose.lao_deg = a->lao_deg;
        pose.cranial_deg = a->cranial_deg;
        applied = move_carm(pose, ctx);
      } else {
        decoded = false;
      }
      break;
    case ControlKind::kCArmGeometry:
      if (const auto g = fluoro_control::read_geometry(c)) {
        flow::CArmPose pose = scope_.carm().pose();
        pose.sid_mm = g->sid_mm;
        pose.table_height_mm = g->table_height_mm;
        pose.fov_mm = g->fov_mm;
        pose.collimation = g->collimation;
        applied = move_carm(pose, ctx);
      } else {
        decoded = false;
      }
      break;
    case ControlKind::kPulseRate:
      if (const auto r = fluoro_control::read_pulse_rate(c)) {
        if (const std::string e = scope_.set_pulse_rate(*r); !e.empty()) {
          log(ctx, "fluoroscopy: %s", e.c_str());
        } else {
          applied = true;
        }
      } else {
        decoded = false;
      }
      break;
    case ControlKind::kRoadmap:
      if (const auto capture = fluoro_control::read_flag(c)) {
        if (!*capture) {
          scope_.clear_roadmap();
          applied = true;
        } else if (scope_.capture_roadmap()) {
          roadmap_ = peak_;
          roadmap_mask_ = peak_mask_;
          log(ctx, "roadmap from pulse %lld", static_cast<long long>(scope_.image().roadmap_pulse));
          applied = true;
        } else {
          log(ctx, "roadmap: no contrast run in this C-arm pose to take it from");
        }
        if (applied) ++inputs_version_;
      } else {
        decoded = false;
      }
      break;
    default: decoded = false; break;
  }
  if (!decoded) log(ctx, "fluoroscopy control kind %u: bad payload of %u bytes", static_cast<unsigned>(c.kind),
                       static_cast<unsigned>(c.size));
  used_ = used_ || applied;
  return applied;
}

bool FluoroUnit::move_carm(const flow::CArmPose& pose, ControlContext& ctx) {
  const bool had_roadmap = scope_.image().roadmap_pulse >= 0;
  if (const std::string e = scope_.set_pose(pose); !e.empty()) {
    log(ctx, "C-arm: %s", e.c_str());
    return false;
  }
  if (had_roadmap && scope_.image().roadmap_pulse < 0) {
    ++inputs_version_;
    log(ctx, "C-arm moved: roadmap removed");
  }
  return true;
}

bool FluoroUnit::inject(const fluoro_control::InjectPayload& injection, ControlContext& ctx) {
  // The catheter the contrast goes through: the held tool, the one it runs in, the first one.
  const std::size_t held = ctx.sim.active_tool();
  auto is_catheter = [this](std::size_t t) { return t < tools_.size() && tools_[t].kind == tool::ToolKind::kCatheter; };
  std::size_t cath = tools_.size();
  if (is_catheter(held)) {
    cath = held;
  } else {
    for (std::size_t t = 0; t < tools_.size(); ++t) {
      if (held < tools_.size() && tools_[t].name == tools_[held].inside && is_catheter(t)) cath = t;
    }
    for (std::size_t t = 0; t < tools_.size() && cath == tools_.size(); ++t) {
      if (is_catheter(t)) cath = t;
    }
  }
  if (cath == tools_.size() || cath >= snap_.tools.size()) {
    log(ctx, "inject: the case has no catheter to inject through");
    return false;
  }
  const glm::dvec3 tip = snap_.tools[cath].tip.position_mm;
  const flow::CenterlinePosition at = transport_.locate(tip);
  const double radius = transport_.locator().radius_at(at.segment, at.arc_mm);
  if (at.distance_mm > radius + kTipOutsideMarginMm) {
    log(ctx, "inject: the %s's tip is %.1f mm from the nearest centreline, outside the vessels", tools_[cath].name.c_str(),
        at.distance_mm);
    return false;
  }
  if (const std::string e = transport_.inject(at, {injection.volume_ml, injection.rate_ml_s, injection.concentration_mgI_ml}); !e.empty()) {
    log(ctx, "inject: %s", e.c_str());
    return false;
  }
  log(ctx, "inject %.1f mL at %.1f mL/s from the %s's tip (segment %d)", injection.volume_ml, injection.rate_ml_s, tools_[cath].name.c_str(),
      network_.model().segments[at.segment].id);
  return true;
}

void FluoroUnit::tick(std::int64_t now_us) {
  // Before the first injection the vessels hold no contrast and, with steady flow, a step would
  // change nothing: the transport rests (its clock only matters to pulsatile flow).
  const bool rest = transport_.injected_mg() == 0.0 && !transport_.injecting() && network_.max_flow_scale() == 1.0;
  while ((transport_steps_ + 1) * transport_step_us_ <= now_us) {
    if (!rest) transport_.step();
    ++transport_steps_;
  }
  const flow::FluoroTick t = scope_.tick(now_us, transport_.injecting());
  if (t.pulsed) capture_pulse(t);
}

void FluoroUnit::capture_pulse(const flow::FluoroTick& t) {
  std::swap(shown_, previous_);  // previous_: the pulse before this one
  std::size_t k = 0;
  const std::size_t segments = network_.model().segments.size();
  for (std::uint32_t s = 0; s < segments; ++s) {
    for (const double c : transport_.cell_concentrations(s)) shown_[k++] = static_cast<float>(c);
  }
  const flow::FluoroImage& image = scope_.image();
  if (t.run_started) run_mask_ = image.mask_pulse == t.pulse || !have_shown_ ? shown_ : previous_;
  have_shown_ = true;
  if (image.run > 0) {
    scope_.report_iodine_in_field(t.pulse, field_.in_field_mg(transport_, scope_.carm()));
    if (scope_.peak_pulse() == t.pulse) {
      peak_ = shown_;
      peak_mask_ = run_mask_;
    }
  }
  // The snapshot lists the case's tools, then the released coils.
  const auto copy = [](const std::vector<glm::dvec3>& from, std::vector<glm::vec3>& to) {
    to.clear();
    const std::size_t n = std::min(from.size(), to.capacity());  // never allocate here
    for (std::size_t j = 0; j < n; ++j) to.push_back(glm::vec3(from[j]));
  };
  const std::size_t tools = std::min(tools_.size(), snap_.tools.size());
  pulse_tool_count_ = static_cast<int>(std::min(tools, kMaxTools));
  for (int i = 0; i < pulse_tool_count_; ++i) {
    copy(snap_.tools[static_cast<std::size_t>(i)].positions_mm, pulse_nodes_[static_cast<std::size_t>(i)]);
  }
  pulse_coil_count_ = static_cast<int>(std::min(snap_.tools.size() - tools, kMaxReleasedCoils));
  for (int i = 0; i < pulse_coil_count_; ++i) {
    copy(snap_.tools[tools + static_cast<std::size_t>(i)].positions_mm, pulse_coil_nodes_[static_cast<std::size_t>(i)]);
  }
  ++inputs_version_;
}

std::uint64_t FluoroUnit::hash(std::uint64_t seed) const {
  base::XxhHasher h;
  h.add(seed);
  const std::size_t segments = network_.model().segments.size();
  for (std::uint32_t s = 0; s < segments; ++s) {
    for (const double c : transport_.cell_concentrations(s)) h.add(c);
  }
  const flow::FluoroImage& im = scope_.image();
  h.add(im.pulse);
  h.add(im.pulse_time_us);
  h.add(im.beam_on);
  h.add(im.run);
  h.add(im.mask_pulse);
  h.add(im.roadmap_pulse);
  const flow::FluoroMetrics& m = scope_.metrics();
  h.add(m.fluoro_time_s);
  h.add(m.dap_Gy_cm2);
  h.add(m.runs);
  h.add(m.pulses);
  const flow::CArmPose& p = scope_.carm().pose();
  for (const double v : {p.lao_deg, p.cranial_deg, p.sid_mm, p.table_height_mm, p.fov_mm, p.collimation}) h.add(v);
  h.add(scope_.pulse_rate());
  h.add(transport_.injected_volume_ml());
  h.add(transport_.injected_mg());
  return h.digest();
}

void FluoroUnit::fill(MetricsCollector& metrics) const {
  const flow::FluoroMetrics& m = scope_.metrics();
  metrics.set_fluoroscopy(m.fluoro_time_s, m.dap_Gy_cm2 * 1e3, m.runs, transport_.injected_volume_ml());
}

void FluoroUnit::publish(FluoroView& v) const {
  v.available = true;
  v.pose = scope_.carm().pose();
  v.image = scope_.image();
  v.pulse_rate_hz = scope_.pulse_rate();
  v.injecting = transport_.injecting();
  v.exposure = scope_.metrics();
  v.contrast_ml = transport_.injected_volume_ml();
  if (v.inputs_version == inputs_version_) return;
  auto set = [](std::vector<float>& to, const std::vector<float>& from, bool present) {
    if (present) {
      to.assign(from.begin(), from.end());  // within the reserved capacity
    } else {
      to.clear();
    }
  };
  set(v.iodine_mgI_ml, shown_, have_shown_);
  set(v.mask_iodine_mgI_ml, run_mask_, v.image.run > 0 && v.image.mask_pulse >= 0);
  set(v.roadmap_iodine_mgI_ml, roadmap_, v.image.roadmap_pulse >= 0);
  set(v.roadmap_mask_iodine_mgI_ml, roadmap_mask_, v.image.roadmap_pulse >= 0);
  v.pulse_tool_count = pulse_tool_count_;
  for (int i = 0; i < pulse_tool_count_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    v.pulse_tool_nodes_mm[k].assign(pulse_nodes_[k].begin(), pulse_nodes_[k].end());
  }
  v.pulse_coil_count = pulse_coil_count_;
  for (int i = 0; i < pulse_coil_count_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    v.pulse_coil_nodes_mm[k].assign(pulse_coil_nodes_[k].begin(), pulse_coil_nodes_[k].end());
  }
  v.inputs_version = inputs_version_;
}

}  // namespace cathbox::session
