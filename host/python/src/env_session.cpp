#include "python/env_session.hpp"

#include <cassert>
#include <cmath>
#include <cstdio>

#include "session/fluoro_controls.hpp"
#include "session/state_hash.hpp"

namespace cathbox::python {

// Each tick: whether every rod's solve converged, and the wall force the metrics read.
class EnvSession::Readings final : public session::TickObserver {
 public:
  explicit Readings(EnvSession& owner) : owner_(owner) {}
  void observe(const session::TickView& view) override {
    // A rod with no node out of its outer tool (the wire still inside the catheter) is not
    // solved this tick: not counted (as session::ContactReadings does).
    bool converged = true;
    for (std::size_t t = 0; t < view.sim.tool_count(); ++t) {
      const tool::Rod& rod = view.sim.rod(t);
      converged = converged && (rod.converged() || rod.first_free_node() >= rod.node_total());
    }
    if (!converged) ++owner_.unconverged_ticks_;
    double wall = 0.0;
    for (std::size_t t = 0; t < view.contacts.size(); ++t) wall = std::max(wall, view.contacts.tool(t).wall_mN);
    owner_.wall_force_mN_ = wall;
  }

 private:
  EnvSession& owner_;
};

EnvSession::EnvSession(EnvSessionOptions options) : options_(std::move(options)) {}

EnvSession::~EnvSession() { (void)close(); }

base::Result<std::unique_ptr<EnvSession>> EnvSession::open(const std::string& case_path,
                                                           const EnvSessionOptions& options) {
  if (options.period_us < 100 || options.period_us > 10'000) {
    return base::Error{"period_us " + std::to_string(options.period_us) + " is outside [100, 10000]"};
  }
  return start(session::load_session_case(case_path), options);
}

base::Result<std::unique_ptr<EnvSession>> EnvSession::start(session::SessionCaseLoad loaded,
                                                            const EnvSessionOptions& options) {
  if (!loaded) return base::Error{loaded.error().message};
  std::unique_ptr<EnvSession> s(new EnvSession(options));
  const double dt_s = static_cast<double>(options.period_us) * 1e-6;
  auto hand = std::make_unique<session::ProgramHand>(dt_s, options.who);
  s->hand_ = hand.get();
  session::SessionOptions so;
  so.period_us = options.period_us;
  so.end_at_target = options.end_at_target;
  // The C-arm looks at the middle of the way: between the entry and the target (else the entry).
  flow::CArmPose pose;
  const glm::dvec3 entry = loaded.value()->entry.point_mm;
  pose.isocenter_mm = loaded.value()->target_mm ? 0.5 * (entry + glm::dvec3(*loaded.value()->target_mm)) : entry;
  s->c_arm_ = flow::CArm(pose);
  s->session_ = std::make_unique<session::Session>(std::move(loaded.value()), std::move(hand), so);
  s->readings_ = std::make_unique<Readings>(*s);
  s->session_->add_observer(*s->readings_);
  if (!options.record_path.empty()) {
    if (base::Status<> recording = s->session_->record_to(options.record_path); !recording) return recording.error();
  }
  s->session_->simulator().copy_snapshot(s->snap_);
  for (std::size_t t = 0; t < s->tool_count(); ++t) s->rod_buffers_.push_back(s->session_->simulator().rod(t).positions().data());
  return s;
}

base::Status<> EnvSession::set_speed(std::size_t tool, double insertion_mm_s, double rotation_rad_s) {
  if (tool >= tool_count()) {
    return base::Error{"tool " + std::to_string(tool) + " out of range: the case has " + std::to_string(tool_count()) +
                       " tool(s)"};
  }
  if (!std::isfinite(insertion_mm_s) || !std::isfinite(rotation_rad_s)) {
    return base::Error{"tool " + std::to_string(tool) + " (" + session_->tool_names()[tool] +
                       "): speed is not finite (insertion " + std::to_string(insertion_mm_s) + " mm/s, rotation " +
                       std::to_string(rotation_rad_s) + " rad/s)"};
  }
  hand_->set_speed(tool, {insertion_mm_s, rotation_rad_s});
  return base::Ok{};
}

std::int64_t EnvSession::step(std::int64_t ticks) {
  if (ticks <= 0 || closed_) return 0;
  Input in;
  for (std::size_t t = 0; t < tool_count(); ++t) in.speeds[t] = hand_->speed(t);
  const std::int64_t ran = session_->step_virtual(ticks);
  in.ticks = ran;
  if (ran > 0) inputs_.push_back(in);
  session_->simulator().copy_snapshot(snap_);
  // The Python module's node buffers view the rods' own arrays: a program's hand only moves the
  // tools (it never loads a coil, the one thing that rebuilds a rod), so they never move.
  for (std::size_t t = 0; t < rod_buffers_.size(); ++t) assert(session_->simulator().rod(t).positions().data() == rod_buffers_[t]);
  return ran;
}

void EnvSession::press_pedal() {
  (void)session_->post(session::fluoro_control::pedal(true));
  pedal_at_.push_back(inputs_.size());
}

std::uint64_t EnvSession::state_hash() const { return session::state_hash(snap_); }

base::Status<> EnvSession::set_c_arm(const flow::CArmPose& pose) {
  const std::string why = flow::check_pose(pose);
  if (!why.empty()) return base::Error{why};
  c_arm_ = flow::CArm(pose);
  return base::Ok{};
}

base::Result<std::unique_ptr<EnvSession>> EnvSession::clone() const {
  EnvSessionOptions o = options_;
  o.record_path.clear();
  auto opened = start(session::session_case_from_record(session_->record_header()), o);
  if (!opened) return opened.error();
  EnvSession& c = *opened.value();
  c.c_arm_ = c_arm_;
  std::size_t pedal = 0;
  for (std::size_t i = 0; i <= inputs_.size(); ++i) {
    for (; pedal < pedal_at_.size() && pedal_at_[pedal] == i; ++pedal) c.press_pedal();
    if (i == inputs_.size()) break;
    const Input& in = inputs_[i];
    for (std::size_t t = 0; t < tool_count(); ++t) c.hand_->set_speed(t, in.speeds[t]);
    if (c.step(in.ticks) != in.ticks) return base::Error{"clone: the replayed session ended early"};
  }
  for (std::size_t t = 0; t < tool_count(); ++t) c.hand_->set_speed(t, hand_->speed(t));
  if (c.state_hash() != state_hash()) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "clone: state hash %016llx after replaying the inputs, %016llx expected",
                  static_cast<unsigned long long>(c.state_hash()), static_cast<unsigned long long>(state_hash()));
    return base::Error{buf};
  }
  return opened;
}

base::Status<> EnvSession::close() {
  if (closed_) return base::Ok{};
  closed_ = true;
  session_->end_run();
  session_->step_virtual(1);  // the run ends at the next tick (the record's end marker)
  if (session::Recorder* r = session_->recorder()) {
    if (!r->close()) return base::Error{"record " + options_.record_path + ": " + r->error()};
  }
  return base::Ok{};
}

}  // namespace cathbox::python
