#include "session/session.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "session/state_hash.hpp"
#include "tool/mesh_wall.hpp"
#include "session_controls.hpp"
#include "tip_feedback.hpp"

#ifndef CATHBOX_VERSION
#define CATHBOX_VERSION "0.0.0"
#endif

namespace cathbox::session {
namespace {

std::int64_t unix_now_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

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
  return real_thread_ ? real_clock().now_us() : tick_ * options_.period_us;
}

void Session::end(record::EndReason reason, std::string text) {
  if (over_.load(std::memory_order_acquire)) return;
  end_reason_ = reason;
  end_text_ = std::move(text);
  if (thrombectomy_) {  // the emboli still in transit are counted now
    thrombectomy_->finish(tick_ * options_.period_us);
    metrics_.set_thrombectomy(thrombectomy_->figures());
  }
  hand_->release();
  log("%s", end_text_.c_str());
  // A real-time run keeps its dropped haptic ticks, its own thread's or those its outside pacer
  // told (a run in virtual time drops none by construction, and has no figure).
  const std::optional<std::int64_t> dropped = real_time_drops();
  if (dropped) metrics_.set_haptic_dropped(*dropped, tick_);
  if (recorder_) recorder_->finish(reason, end_text_, tick_, unix_now_us(), dropped);
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
  sim_->step(static_cast<double>(options_.period_us) * 1e-6);  // the wall's pulse first (pulse_wall)
  log_partings();
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

// The wall distends with the pulse (one sine and a multiply per segment; no allocation), for
// the tick being stepped: run by the simulator at the start of its step, once the released
// coils' solve the last step left running is over (Simulator::set_before_solves).
void Session::pulse_wall() {
  const double t_s = static_cast<double>(tick_ * options_.period_us) * 1e-6;
  wall_field_->set_pressure_kPa(pulse_mean_kPa_ * (scene_->flow->flow_scale(t_s) - 1.0));
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
  set_tip_feedback(fb, held);
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
    metrics_.set_coiling(fig);
    const tool::CoilSleep& sleep = sim_->coil_sleep();
    metrics_.set_coil_sleep(static_cast<std::int64_t>(sleep.skipped_steps()), static_cast<std::int64_t>(sleep.wakes()));
    if (coil_metrics_->herniation_began()) log("coil herniating into the parent artery (%d nodes past the neck)", fig.herniated_nodes);
  }
  log_events(held.tip_segment, mt.tip_force_mN);
  if (!observers_.empty()) {
    const TickView view{n, mt.time_us, *sim_, snap_, input_, std::span(applied_.data(), applied_count_), metrics_.metrics(), contacts_,
                        thrombectomy_.get()};
    for (TickObserver* o : observers_) o->observe(view);
  }
}

// A coil's detachment zone that stopped parting this tick (Simulator::detach): its coil released,
// or the zone drawn back into the catheter before it parted (the coil still attached).
void Session::log_partings() {
  for (std::size_t t = 0; t < input_.tool_count && t < parting_.size(); ++t) {
    const bool now = sim_->parting(t);
    if (parting_[t] && !now) {
      if (sim_->released_mm(t) > 0.0) {
        log("coil of the %s detached", tool_names_[t].c_str());
      } else {
        log("the %s's coil not detached: its zone was drawn back into the catheter", tool_names_[t].c_str());
      }
    }
    parting_[t] = now;
  }
}

// The tick's events in the log (and the target in the record); the box's link and faults.
void Session::log_events(int tip_segment, double tip_force_mN) {
  // The tip's own force (not the tick's largest contact, which may be another tool's shaft).
  // Where: a vessel segment, a junction's wall (MeshWall::kJunction, no one segment), or no
  // segment found (-1); never a raw negative id.
  if (metrics_.contact_began()) {
    if (tip_segment >= 0) log("tip on the wall, segment %d (%.1f mN)", tip_segment, tip_force_mN);
    else log("tip on the wall%s (%.1f mN)", tip_segment == tool::MeshWall::kJunction ? " at a junction" : "", tip_force_mN);
  }
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

}  // namespace cathbox::session
