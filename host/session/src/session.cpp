#include "session/session.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>

#include "session/state_hash.hpp"
#include "scenario/case_wall.hpp"

#ifndef CATHBOX_VERSION
#define CATHBOX_VERSION "0.0.0"
#endif

namespace cathbox::session {
namespace {

glm::vec3 to_f(const glm::dvec3& v) { return glm::vec3(v); }

std::int64_t unix_now_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

// Controls the hand issues go straight to the session's apply().
class Session::Sink final : public ControlSink {
 public:
  explicit Sink(Session& s) : s_(s) {}
  void push(const Control& control) override { s_.apply(control); }

 private:
  Session& s_;
};

// kSelectTool: the hand takes another tool (payload: its index, or 0xFF for the next one).
class Session::SelectTool final : public ControlHandler {
 public:
  explicit SelectTool(Session& s) : s_(s) {}
  bool apply(Control& c, ControlContext& ctx) override {
    if (c.size != 1) return false;
    const std::size_t count = ctx.sim.tool_count();
    std::size_t next = c.payload[0];
    if (next == 0xFF) next = (ctx.sim.active_tool() + 1) % count;
    if (next >= count || next == ctx.sim.active_tool()) return false;
    ctx.sim.select(next);
    ctx.hand.hold(next, ctx.input.tools[next]);
    c.payload[0] = static_cast<std::uint8_t>(next);  // recorded as the tool it became
    s_.tool_changed_ = true;
    s_.held_.store(next, std::memory_order_relaxed);
    s_.log("now holding the %s", s_.tool_names_[next].c_str());
    return true;
  }

 private:
  Session& s_;
};

// kDetachCoil: release a coil tool's coil (payload: the tool's index). Refused (not applied,
// not recorded) while the detachment zone is still in the catheter.
class Session::DetachCoil final : public ControlHandler {
 public:
  explicit DetachCoil(Session& s) : s_(s) {}
  bool apply(Control& c, ControlContext& ctx) override {
    if (c.size != 1) return false;
    if (!s_.device_done(ctx.sim.detach(c.payload[0]), "detach")) return false;
    s_.log("coil of the %s detached", s_.tool_names_[c.payload[0]].c_str());
    return true;
  }

 private:
  Session& s_;
};

// kLoadCoil: the coil tool's old pusher withdrawn, its next coil fed at the hub (payload: the
// tool's index). Refused (not applied, not recorded) before its coil is detached or when the
// case lists no further coil.
class Session::LoadCoil final : public ControlHandler {
 public:
  explicit LoadCoil(Session& s) : s_(s) {}
  bool apply(Control& c, ControlContext& ctx) override {
    if (c.size != 1) return false;
    if (!s_.device_done(ctx.sim.load_next_coil(c.payload[0]), "load_coil")) {
      if (ctx.hand.kind() == HandKind::kActionScript) {
        // The script has already moved on to the next coil: its motions would drive the coil
        // still attached from the hub (a pull of its whole length in one tick).
        s_.log("the script's next coil is not loaded: run ended");
        s_.end_run();
      }
      return false;
    }
    const std::size_t t = c.payload[0];
    if (t < kMaxTools) {
      s_.update_max_insertion(t);
      // The new pusher starts at the hub: every hand driving this tool carries on from 0.
      s_.input_.tools[t] = ToolCommand{};
      ctx.hand.restart(t, s_.input_.tools[t]);
    }
    s_.coil_loaded_ = t == ctx.sim.active_tool();  // the held tool's samples start again
    s_.log("next coil loaded on the %s", s_.tool_names_[t].c_str());
    return true;
  }

 private:
  Session& s_;
};

// kBalloon: the inflation device of a balloon tool (payload: tool, BalloonOp, f64 value). A
// value the balloon does not take is refused (not applied, not recorded) with a log line.
class Session::BalloonControl final : public ControlHandler {
 public:
  explicit BalloonControl(Session& s) : s_(s) {}
  bool apply(Control& c, ControlContext& ctx) override {
    if (c.size != 10 || c.payload[1] > 2) return false;
    const std::size_t tool = c.payload[0];
    std::uint64_t bits = 0;
    for (int i = 0; i < 8; ++i) bits |= static_cast<std::uint64_t>(c.payload[2 + i]) << (8 * i);
    double value = 0.0;
    std::memcpy(&value, &bits, sizeof value);
    const auto op = static_cast<BalloonOp>(c.payload[1]);
    const tool::DeviceError e = op == BalloonOp::kInflatePressure ? ctx.sim.inflate_pressure(tool, value)
                                : op == BalloonOp::kInflateVolume  ? ctx.sim.inflate_volume(tool, value)
                                                                   : ctx.sim.deflate(tool);
    if (e != tool::DeviceError::kNone) {
      s_.log("balloon: refused (%s)", tool::device_error_text(e));
      return false;
    }
    if (op == BalloonOp::kDeflate) {
      s_.log("balloon of the %s: deflate", s_.tool_names_[tool].c_str());
    } else {
      s_.log("balloon of the %s: inflate to %.2f %s", s_.tool_names_[tool].c_str(), value,
             op == BalloonOp::kInflatePressure ? "atm" : "ml");
    }
    return true;
  }

 private:
  Session& s_;
};

Session::Session(std::unique_ptr<SessionCase> scene, std::unique_ptr<Hand> hand, SessionOptions options)
    : scene_(std::move(scene)), hand_(std::move(hand)), options_(options) {
  hand_description_ = hand_->describe();
  every_law_ = hand_->feels_every_tool();
  const std::vector<tool::ToolSpec>& tools = scene_->spec.tools;
  for (const tool::ToolSpec& t : tools) tool_names_.push_back(t.name);
  build_simulator();
  input_.tool_count = std::min(tools.size(), kMaxTools);
  contacts_ = ContactReadings(tools.size());
  for (std::size_t t = 0; t < input_.tool_count; ++t) update_max_insertion(t);
  if (options_.held_tool && *options_.held_tool < input_.tool_count) sim_->select(*options_.held_tool);
  input_.held = sim_->active_tool();
  held_.store(input_.held, std::memory_order_relaxed);
  hand_->hold(input_.held, input_.tools[input_.held]);

  MetricsSettings ms;
  ms.target_mm = scene_->target_mm;
  ms.target_radius_mm = scene_->target_radius_mm;
  ms.route_length_mm = scene_->route_length_mm;
  ms.route_segments = scene_->route_segment_ids;
  ms.wall_force_threshold_mN = scene_->wall_force_threshold_mN;
  metrics_ = MetricsCollector(std::move(ms));

  select_tool_ = std::make_unique<SelectTool>(*this);
  sink_ = std::make_unique<Sink>(*this);
  add_control_handler(static_cast<std::uint16_t>(ControlKind::kSelectTool), *select_tool_);
  if (scene_->flow) {
    add_flow_units();
  } else if (!scene_->flow_error.empty()) {
    log("no fluoroscopy: %s", scene_->flow_error.c_str());
  }
  add_device_units();
  if (hand_->kind() == HandKind::kReplay) controls_.close();  // a replay applies the record's only

  const std::size_t nodes = options_.max_nodes_per_tool;
  const std::size_t cells = fluoro_ ? fluoro_->cells().size() : 0;
  exchange_.prepare_slots([nodes, cells](SceneSnapshot& s) {
    s.reserve(nodes);
    s.fluoro.reserve(cells, nodes);
  });
  sim_->copy_snapshot(snap_);
  if (thrombectomy_) thrombectomy_->tick(0, snap_);  // the tips, before the first control
  // The hand sees where the tool starts before the first tick.
  HandFeedback fb;
  fb.tick = -1;
  fb.held = input_.held;
  const tool::ToolSnapshot& held = snap_.tools[input_.held];
  fb.tip_mm = to_f(held.tip.position_mm);
  fb.tip_direction = to_f(held.tip.direction);
  fb.tip_bend = to_f(held.tip.normal);
  hand_->feel(fb);
  publish();
}

// The simulator on the case's wall: a balloon case's own first wall (the angioplasty unit's),
// else the world's; a compliant wall when the case gives one.
void Session::build_simulator() {
  const std::vector<tool::ToolSpec>& tools = scene_->spec.tools;
  const bool balloon = std::any_of(tools.begin(), tools.end(), [](const tool::ToolSpec& t) { return t.balloon.present(); });
  if (balloon && scene_->world->source_model() != nullptr) {
    // Its own first wall, the same as the world's (the world's stays for picking), built by the
    // builder of the next walls so that they reuse the regions the balloon leaves alone.
    tool::WallBuilder builder = tool::cached_mesh_wall_builder();
    auto wall = builder(*scene_->world->source_model());
    if (wall) {
      angioplasty_ = std::make_unique<tool::Angioplasty>(*scene_->world->source_model(), std::move(*wall),
                                                         tool::WallSwap::Mode::kSynchronous, tool::LumenRemodelParams{},
                                                         std::move(builder));
    }
  }
  sim_ = std::make_unique<tool::Simulator>(angioplasty_ ? angioplasty_->wall() : scene_->world->wall(), tools, scene_->entry);
  tool::use_case_wall(*sim_, scene_->spec.wall ? &*scene_->spec.wall : nullptr);  // a compliant wall
}

// A case with a vessel network: the fluoroscopy unit, and the thrombectomy unit when it has clots.
void Session::add_flow_units() {
  const std::vector<tool::ToolSpec>& tools = scene_->spec.tools;
  // The C-arm starts in the case's first working projection (else AP), centred on its target.
  flow::CArmPose pose;
  if (!scene_->spec.views.empty()) {
    pose.lao_deg = scene_->spec.views.front().lao_deg;
    pose.cranial_deg = scene_->spec.views.front().cranial_deg;
  }
  if (scene_->target_mm) pose.isocenter_mm = glm::dvec3(*scene_->target_mm);
  fluoro_ = std::make_unique<FluoroUnit>(*scene_->flow, tools, snap_, options_.max_nodes_per_tool, pose);
  for (const ControlKind k : FluoroUnit::kKinds) add_control_handler(static_cast<std::uint16_t>(k), *fluoro_);
  fluoro_->fill(metrics_);
  std::string why_not;
  thrombectomy_ = ThrombectomyUnit::make(*scene_->flow, scene_->spec, events_, why_not);
  if (thrombectomy_) {
    for (const ControlKind k : ThrombectomyUnit::kKinds) add_control_handler(static_cast<std::uint16_t>(k), *thrombectomy_);
    metrics_.set_thrombectomy(thrombectomy_->figures());
  } else if (!why_not.empty()) {
    log("no thrombectomy grading: %s", why_not.c_str());
  }
}

// The coil and balloon controls, the coiling figures for a case with a sac, and whether the run
// ends at the target: coiling, angioplasty and thrombectomy go on there (the neck, the lesion,
// the clot).
void Session::add_device_units() {
  detach_coil_ = std::make_unique<DetachCoil>(*this);
  add_control_handler(static_cast<std::uint16_t>(ControlKind::kDetachCoil), *detach_coil_);
  load_coil_ = std::make_unique<LoadCoil>(*this);
  add_control_handler(static_cast<std::uint16_t>(ControlKind::kLoadCoil), *load_coil_);
  if (scene_->world->sac()) {
    coil_metrics_.emplace(*sim_, *scene_->world->sac());
    if (!coil_metrics_->has_coils()) coil_metrics_.reset();
  }
  balloon_control_ = std::make_unique<BalloonControl>(*this);
  add_control_handler(static_cast<std::uint16_t>(ControlKind::kBalloon), *balloon_control_);
  if (coil_metrics_ || angioplasty_ || thrombectomy_) options_.end_at_target = false;
}

Session::~Session() {
  stop();
  if (!over_.load(std::memory_order_acquire)) end(record::EndReason::kStopped, "stopped");
  if (recorder_) (void)recorder_->close();
}

RecordHeader Session::record_header() const {
  RecordHeader h;
  h.software_version = CATHBOX_VERSION;
  h.start_unix_us = unix_now_us();
  h.case_name = scene_->name;
  h.case_file = scene_->case_file;
  h.case_text = scene_->case_text;
  h.vessel_file = scene_->vessel_file;
  h.vessel_text = scene_->vessel_text;
  h.surface_file = scene_->surface_file;
  h.surface_bytes = scene_->surface_bytes;
  h.tools = scene_->spec.tools;
  h.entry = scene_->entry;
  h.held_tool = input_.held;
  h.hand = hand_->kind();
  h.hand_description = hand_description_;
  h.device = hand_->device();
  h.period_us = options_.period_us;
  h.hash_every = options_.hash_every;
  return h;
}

base::Status<> Session::record_to(const std::string& path) {
  if (tick_ > 0) return base::Error{path + ": a session records from its first tick"};
  base::Result<std::unique_ptr<Recorder>> recorder = Recorder::create(path, record_header());
  if (!recorder) return recorder.error();
  recorder_ = std::move(*recorder);
  return base::Ok{};
}

void Session::add_control_handler(std::uint16_t kind, ControlHandler& handler) {
  if (kind < handlers_.size()) handlers_[kind] = &handler;
}

void Session::add_observer(TickObserver& observer) { observers_.push_back(&observer); }

bool Session::device_done(tool::DeviceError e, const char* verb) {
  if (e == tool::DeviceError::kNone) return true;
  log("%s refused: %s", verb, tool::device_error_text(e));
  return false;
}

void Session::observe_convergence() {
  const std::size_t tools = sim_->tool_count();
  const std::size_t seen = metrics_.metrics().convergence.size();
  for (std::size_t t = 0; t < contacts_.size(); ++t) {
    std::string name;  // built once per tool (metric names are unique: a released coil is numbered)
    if (t >= seen && t < snap_.tools.size()) {
      // A released coil's rod is named "<coil tool> (detached)": "<coil tool>_released_<k>".
      const std::string& full = snap_.tools[t].name;
      name = t < tools ? full : full.substr(0, full.find(" (")) + "_released_" + std::to_string(t - tools + 1);
    }
    metrics_.set_convergence(t, name, contacts_.solved_ticks(t), contacts_.held_ticks(t));
  }
}

void Session::update_max_insertion(std::size_t t) {
  input_.max_insertion_um[t] = static_cast<std::int64_t>(std::floor(sim_->max_insertion_mm(t) * 1e3));
}

void Session::log(const char* fmt, ...) {
  char buf[112];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  (void)events_.push(tick_ * options_.period_us, buf);
}

void Session::apply(Control control) {
  ControlHandler* handler = control.kind < handlers_.size() ? handlers_[control.kind] : nullptr;
  if (handler == nullptr) {
    log("control kind %u has no handler here: ignored", static_cast<unsigned>(control.kind));
    return;
  }
  if (applied_count_ == applied_.size()) {
    log("more than %zu controls in one tick: ignored", applied_.size());
    return;
  }
  ControlContext ctx{tick_, tick_ * options_.period_us, *sim_, *hand_, events_, input_};
  if (handler->apply(control, ctx)) applied_[applied_count_++] = control;
}

std::int64_t Session::clock_now_us() {
  return real_thread_ ? steady_.now_us() : tick_ * options_.period_us;
}

void Session::end(record::EndReason reason, std::string text) {
  if (over_.load(std::memory_order_acquire)) return;
  end_reason_ = reason;
  end_text_ = std::move(text);
  hand_->release();
  log("%s", end_text_.c_str());
  if (recorder_) recorder_->finish(reason, end_text_, tick_, unix_now_us());
  over_.store(true, std::memory_order_release);
  publish();
}

bool Session::tick() {
  if (over_.load(std::memory_order_acquire)) return false;  // a finished run stays as it ended
  const std::int64_t n = tick_;
  if (ends_before(n)) return false;
  // 1. Controls: the UI's, then the hand's own.
  applied_count_ = 0;
  tool_changed_ = false;
  coil_loaded_ = false;
  Control c;
  for (int i = 0; i < 32 && controls_.pop(c); ++i) apply(c);
  hand_->controls(n, *sink_);
  if (hand_->finished()) {  // e.g. an action script's `end`: stop before stepping
    end(record::EndReason::kHandFinished, hand_->finish_reason());
    return false;
  }
  read_hand(n);
  step_world(n);
  const HandFeedback fb = feel(n);
  observe(n, fb);
  if (recorder_) recorder_->end_tick();
  tick_ = n + 1;
  ticks_.store(tick_, std::memory_order_release);
  // 6. The end of the run?
  if (options_.end_at_target && metrics_.target_just_reached()) {
    end(record::EndReason::kTargetReached, "target reached");
  } else if (hand_->finished()) {
    end(record::EndReason::kHandFinished, hand_->finish_reason());
  }
  if (over_.load(std::memory_order_relaxed)) return false;
  publish();
  return true;
}

bool Session::ends_before(std::int64_t n) {
  if (options_.max_ticks >= 0 && n >= options_.max_ticks) {
    char text[64];
    std::snprintf(text, sizeof text, "time limit of %.3f s", static_cast<double>(n * options_.period_us) * 1e-6);
    end(record::EndReason::kTimeLimit, text);
    return true;
  }
  if (end_requested_.load(std::memory_order_acquire)) {
    end(record::EndReason::kEndedByUser, "run ended by the trainee");
    return true;
  }
  return false;
}

// 2. The hand: where the tools are, clamped to their range; the tick's inputs recorded.
void Session::read_hand(std::int64_t n) {
  input_.held = sim_->active_tool();
  hand_->read(n, input_);
  for (std::size_t t = 0; t < input_.tool_count; ++t) {
    input_.tools[t].insertion_um = std::clamp(input_.tools[t].insertion_um, std::int64_t{0}, input_.max_insertion_um[t]);
  }
  if (recorder_) {
    recorder_->begin_tick(n, clock_now_us());
    for (std::size_t i = 0; i < applied_count_; ++i) recorder_->control(applied_[i]);
    recorder_->tools(input_);
    recorder_->box(input_.box);
  }
}

// 3. The simulation, then the procedures that follow it (balloon, fluoroscopy, thrombectomy).
void Session::step_world(std::int64_t n) {
  for (std::size_t t = 0; t < input_.tool_count; ++t) {
    sim_->set_insertion(t, static_cast<double>(input_.tools[t].insertion_um) * 1e-3);
    sim_->set_rotation(t, static_cast<double>(input_.tools[t].rotation_urad) * 1e-6);
  }
  sim_->step(static_cast<double>(options_.period_us) * 1e-6);
  if (angioplasty_) {
    angioplasty_->after_step(*sim_);
    const tool::AngioplastyFigures f = angioplasty_->figures(*sim_);
    if (f.rupture_risk_events > rupture_events_) log("balloon over-sized: %.2fx the reference diameter (rupture risk)", f.max_oversize_ratio);
    rupture_events_ = f.rupture_risk_events;
    metrics_.set_angioplasty(f);
  }
  sim_->copy_snapshot(snap_);
  // The fluoroscopy unit and the contrast, to the end of this tick.
  if (fluoro_ && thrombectomy_ && thrombectomy_->flow_generation() != flow_generation_) {
    flow_generation_ = thrombectomy_->flow_generation();  // a pass or an arrest solved the network again
    fluoro_->flows_changed();
  }
  if (fluoro_) fluoro_->tick((n + 1) * options_.period_us);
  if (thrombectomy_) {
    thrombectomy_->tick(n * options_.period_us, snap_);
    thrombectomy_->after_step(n * options_.period_us, *sim_);
    // The figures change only with a pass, and every pass solves the network again: copy them
    // then, not on every tick (the copy allocates).
    if (thrombectomy_->flow_generation() != figures_generation_) {
      figures_generation_ = thrombectomy_->flow_generation();
      metrics_.set_thrombectomy(thrombectomy_->figures());
    }
    if (thrombectomy_->arrested()) metrics_.set_flow_arrest(thrombectomy_->figures().balloon_guide_inflations, thrombectomy_->figures().flow_arrest_s);
  }
}

// 4. What the hand feels: the held tool's force law (every tool's for a hand that feels them
// all), its tip, and the state hash every hash_every ticks.
HandFeedback Session::feel(std::int64_t n) {
  const std::size_t held_index = input_.held;
  const tool::ToolSnapshot& held = snap_.tools[held_index];
  HandFeedback fb;
  fb.tick = n;
  fb.held = held_index;
  fb.law = sim_->force_law(held_index);
  if (every_law_) {
    fb.tool_count = input_.tool_count;
    for (std::size_t t = 0; t < input_.tool_count; ++t) fb.laws[t] = t == held_index ? fb.law : sim_->force_law(t);
  }
  fb.tip_mm = to_f(held.tip.position_mm);
  fb.tip_direction = to_f(held.tip.direction);
  fb.tip_bend = to_f(held.tip.normal);
  fb.hand_force_mN = held.hand_force_mN;
  if ((n + 1) % options_.hash_every == 0) {
    // The fluoroscopy unit's state joins the hash once it has been used (older records keep theirs).
    const std::uint64_t h = state_hash(snap_);
    fb.state_hash = fluoro_ && fluoro_->used() ? fluoro_->hash(h) : h;
  }
  hand_->feel(fb);
  if (recorder_ && fb.state_hash) recorder_->state_hash(*fb.state_hash);
  return fb;
}

// 5. Metrics and events.
void Session::observe(std::int64_t n, const HandFeedback& fb) {
  const std::size_t held_index = input_.held;
  const tool::ToolSnapshot& held = snap_.tools[held_index];
  MetricsTick mt;
  mt.time_us = n * options_.period_us;
  mt.held = held_index;
  mt.tool_changed = tool_changed_;
  mt.tool_replaced = coil_loaded_;
  mt.held_insertion_mm = static_cast<double>(input_.tools[held_index].insertion_um) * 1e-3;
  mt.tip_mm = fb.tip_mm;
  mt.tip_segment = held.tip_segment;
  mt.hand_force_mN = std::abs(held.hand_force_mN);
  // Wall forces from the steps that converged (contact_readings.hpp).
  contacts_.update(*sim_, snap_);
  mt.wall_force_mN = contacts_.wall_mN();
  mt.tip_in_contact = contacts_.tool(held_index).tip_in_contact;
  mt.tip_force_mN = contacts_.tool(held_index).tip_mN;
  metrics_.observe(mt);
  observe_convergence();
  if (fluoro_) fluoro_->fill(metrics_);
  if (coil_metrics_) {
    coil_metrics_->observe(*sim_);
    const tool::CoilFigures& fig = coil_metrics_->figures();
    metrics_.set_coiling(100.0 * fig.packing_density, fig.deployed_mm, fig.herniations, fig.kick_back_mm);
    if (coil_metrics_->herniation_began()) log("coil herniating into the parent artery (%d nodes past the neck)", fig.herniated_nodes);
  }
  log_events(held.tip_segment, mt.tip_force_mN);
  if (!observers_.empty()) {
    const TickView view{n, mt.time_us, *sim_, snap_, input_, std::span(applied_.data(), applied_count_), metrics_.metrics(), contacts_};
    for (TickObserver* o : observers_) o->observe(view);
  }
}

// The tick's events in the log (and the target in the record); the box's link and faults.
void Session::log_events(int tip_segment, double tip_force_mN) {
  // The tip's own force (not the tick's largest contact, which may be another tool's shaft).
  if (metrics_.contact_began()) log("tip on the wall, segment %d (%.1f mN)", tip_segment, tip_force_mN);
  if (metrics_.target_just_reached()) {
    log("target reached: %.1f mm of tip travel", metrics_.metrics().tip_path_mm);
    if (recorder_) recorder_->event(record::EventCode::kTargetReached);
  }
  if (input_.box.present && input_.box != last_box_) {
    if (input_.box.link_up != last_box_.link_up) log("box link %s", input_.box.link_up ? "up" : "down");
    if (input_.box.faults != last_box_.faults) log("box faults 0x%02x", static_cast<unsigned>(input_.box.faults));
  }
  last_box_ = input_.box;
}

void Session::publish() {
  SceneSnapshot& s = exchange_.write_slot();
  s.sim_time_us = tick_ * options_.period_us;
  s.tick = tick_;
  const std::size_t active = sim_->active_tool();
  s.held_tool = active;
  s.held_coil_attached = sim_->carries_attached_coil(active);
  s.held_next_coil = !s.held_coil_attached && sim_->has_next_coil(active);
  // The snapshot lists the case's tools, then the released coils (copied within the reserved
  // capacity: publishing never allocates).
  const auto copy_nodes = [](const tool::ToolSnapshot& t, ToolView& tv) {
    tv.nodes_mm.clear();
    tv.frames.clear();
    const std::size_t n = std::min(t.positions_mm.size(), tv.nodes_mm.capacity());  // never allocate here
    for (std::size_t k = 0; k < n; ++k) {
      tv.nodes_mm.push_back(to_f(t.positions_mm[k]));
      tv.frames.push_back(k < t.normals.size() ? to_f(t.normals[k]) : glm::vec3(0.0F));
    }
    tv.radius_mm = t.radii_mm.empty() ? 0.2F : *std::max_element(t.radii_mm.begin(), t.radii_mm.end());
  };
  const std::size_t tools = std::min(sim_->tool_count(), snap_.tools.size());
  s.tool_count = static_cast<int>(std::min<std::size_t>(tools, SceneSnapshot::kMaxTools));
  s.contacts.clear();
  for (int i = 0; i < s.tool_count; ++i) {
    const tool::ToolSnapshot& t = snap_.tools[static_cast<std::size_t>(i)];
    ToolView& tv = s.tools[static_cast<std::size_t>(i)];
    tv.active = static_cast<std::size_t>(i) == active;
    copy_nodes(t, tv);
    const std::vector<tool::ToolSpec>& specs = scene_->spec.tools;
    const bool stent = static_cast<std::size_t>(i) < specs.size() && specs[static_cast<std::size_t>(i)].stent.present();
    tv.stent_length_mm = stent ? static_cast<float>(specs[static_cast<std::size_t>(i)].stent.length_mm) : 0.0F;
    tv.wire_radius_mm = stent && !t.radii_mm.empty() ? *std::min_element(t.radii_mm.begin(), t.radii_mm.end()) : 0.0F;
    for (const tool::RodContact& c : t.contacts) {
      if (s.contacts.size() == SceneSnapshot::kMaxContacts) break;
      s.contacts.push_back({to_f(c.point_mm), static_cast<float>(c.normal_force_mN)});
    }
  }
  s.coil_count = static_cast<int>(std::min<std::size_t>(snap_.tools.size() - tools, SceneSnapshot::kMaxCoils));
  for (int i = 0; i < s.coil_count; ++i) {
    ToolView& cv = s.coils[static_cast<std::size_t>(i)];
    cv.active = false;
    const tool::ToolSnapshot& coil = snap_.tools[tools + static_cast<std::size_t>(i)];
    copy_nodes(coil, cv);
    // The primary wind's radius: the node at the cut may carry the pusher's (a wider end node).
    if (!coil.radii_mm.empty()) cv.radius_mm = coil.radii_mm[coil.radii_mm.size() / 2];
  }
  if (active < snap_.tools.size()) {
    const tool::ToolSnapshot& held = snap_.tools[active];
    s.tip_mm = to_f(held.tip.position_mm);
    s.tip_direction = to_f(held.tip.direction);
    s.tip_up = to_f(held.tip.normal);
    s.insertion_mm = held.insertion_mm;
    s.rotation_rad = held.rotation_rad;
    s.hand_force_mN = held.hand_force_mN;
    s.hand_torque_mNmm = held.hand_torque_mNmm;
  }
  const HapticThread* t = active_thread();
  s.haptic_rate_hz = t ? t->rate_hz() : 0.0;
  s.haptic_ticks = tick_;
  s.dropped_ticks = t ? t->dropped() : 0;
  s.metrics = metrics_.metrics();
  s.wall_force_mN = contacts_.wall_mN();
  if (fluoro_) fluoro_->publish(s.fluoro);
  s.run_over = over_.load(std::memory_order_relaxed);
  s.wall_generation = angioplasty_ ? angioplasty_->swap().generation() : 0;
  if (thrombectomy_) {
    const std::optional<std::size_t> a = thrombectomy_->first_aspirator();
    const std::optional<std::size_t> b = thrombectomy_->first_balloon_guide();
    s.aspiration_tool = a ? static_cast<int>(*a) : -1;
    s.aspirating = a && thrombectomy_->aspirating(*a);
    s.balloon_guide_tool = b ? static_cast<int>(*b) : -1;
    s.flow_arrest = thrombectomy_->arrested();
  }
  exchange_.publish();
}

const std::vector<FluoroCell>& Session::fluoro_cells() const {
  static const std::vector<FluoroCell> kNone;
  return fluoro_ ? fluoro_->cells() : kNone;
}

std::shared_ptr<const tool::WallSurface> Session::wall_surface() const {
  if (!angioplasty_ || angioplasty_->swap().generation() == 0) return {};
  return angioplasty_->swap().surface();
}

const HapticThread* Session::active_thread() const {
  return real_thread_ ? real_thread_.get() : virtual_thread_.get();
}

void Session::start() {
  if (angioplasty_) angioplasty_->swap().set_mode(tool::WallSwap::Mode::kWorker);  // never waits on the haptic thread
  if (!real_thread_) {
    real_thread_ = std::make_unique<HapticThread>(steady_, options_.period_us, [this](std::int64_t) { return tick(); });
  }
  real_thread_->start();
}

void Session::stop() {
  if (real_thread_) real_thread_->stop();
}

std::int64_t Session::step_virtual(std::int64_t ticks) {
  if (angioplasty_) angioplasty_->swap().set_mode(tool::WallSwap::Mode::kSynchronous);  // same walls at the same ticks
  if (!virtual_thread_) {
    virtual_thread_ =
        std::make_unique<HapticThread>(virtual_clock_, options_.period_us, [this](std::int64_t) { return tick(); });
  }
  const std::int64_t before = tick_;
  virtual_thread_->run(base::stop_token{}, virtual_thread_->ticks() + ticks);
  return tick_ - before;
}

double Session::haptic_rate_hz() const { return active_thread() ? active_thread()->rate_hz() : 0.0; }
std::int64_t Session::dropped_ticks() const { return active_thread() ? active_thread()->dropped() : 0; }
std::int64_t Session::haptic_cpu_time_us() const { return active_thread() ? active_thread()->cpu_time_us() : 0; }

std::string Session::haptic_scheduling() const {
  return real_thread_ ? ThreadPriority::name(real_thread_->scheduling()) : "virtual time";
}

}  // namespace cathbox::session
