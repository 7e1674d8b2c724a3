// TrainerSession on the project's simulator: the case (tool module's case file, or a bare HCLM
// file with the default guidewire), the vessel module's surface for the views, the tool
// module's simulator against the case's wall, and a hand: the box (with the keyboard on top),
// the keyboard alone, or the scripted hand.
#include "app/trainer_session.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <filesystem>

#include <glm/geometric.hpp>

#include "app/centerline_path.hpp"
#include "app/clock.hpp"
#include "app/haptic_thread.hpp"
#include "app/run_metrics.hpp"
#include "app/scripted_hand.hpp"
#if CATHBOX_TRAINER_HAS_BOX
#include "app/box_hand.hpp"
#endif
#include "tool/case_file.hpp"
#include "collision/obb_tree.hpp"
#include "tool/mesh_wall.hpp"
#include "tool/simulator.hpp"
#include "tool/snapshot.hpp"
#include "vessel/hclm.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::app {
namespace {

constexpr std::int64_t kPeriodUs = 1000;
constexpr double kDtS = 1e-3;
// Above this the global view gets a coarser surface (level L-1, 4-point rings): it shows the
// vessels at ~0.3 mm per pixel, and every triangle costs a software rasteriser the same.
constexpr std::size_t kOverviewTriangles = 40'000;
constexpr double kScriptedLimitS = 120.0;
constexpr std::size_t kMaxNodesPerTool = 2048;

glm::vec3 to_f(const glm::dvec3& v) { return glm::vec3(v); }

std::vector<PathSegment> path_segments(const vessel::VesselModel& model) {
  std::vector<PathSegment> out(model.segments.size());
  for (std::size_t i = 0; i < model.segments.size(); ++i) {
    const vessel::Segment& s = model.segments[i];
    for (const vessel::CenterlinePoint& p : s.points) out[i].points_mm.push_back(glm::vec3(p.pos_mm));
    for (std::int32_t id : s.parents) {
      if (const auto k = model.index_of(id)) out[i].parents.push_back(*k);
    }
    for (std::int32_t id : s.children) {
      if (const auto k = model.index_of(id)) out[i].children.push_back(*k);
    }
  }
  return out;
}

// Without an entry in the case: the start of the root segment (the first without parents),
// pointing along it, as the tool module's case file documents.
tool::Entry root_entry(const vessel::VesselModel& model) {
  tool::Entry e;
  for (const vessel::Segment& s : model.segments) {
    if (!s.parents.empty() || s.points.size() < 2) continue;
    e.point_mm = s.points.front().pos_mm;
    const glm::dvec3 d = s.points[std::min<std::size_t>(2, s.points.size() - 1)].pos_mm - e.point_mm;
    if (glm::length(d) > 1e-9) e.direction = glm::normalize(d);
    break;
  }
  return e;
}

double radius_near(const vessel::VesselModel& model, const glm::vec3& p) {
  double best_d = 1e300;
  double r = 1.0;
  for (const vessel::Segment& s : model.segments) {
    for (const vessel::CenterlinePoint& q : s.points) {
      const double d = static_cast<double>(glm::distance(glm::vec3(q.pos_mm), p));
      if (d < best_d) {
        best_d = d;
        r = q.radius_mm;
      }
    }
  }
  return r;
}

class SimTrainerSession final : public TrainerSession {
 public:
  bool load(const SessionConfig& config, std::string& error);

  const vessel::SurfaceMesh& vessel_mesh() const override { return surface_.mesh; }
  const vessel::SurfaceMesh& overview_mesh() const override { return overview_; }
  std::optional<glm::vec3> target_mm() const override { return target_; }
  float target_radius_mm() const override { return target_radius_mm_; }
  std::string case_name() const override { return case_name_; }
  std::string vessel_file() const override { return vessel_file_; }
  std::string device_status() const override { return device_status_; }
  std::string active_tool_name() const override { return tool_names_[active_.load(std::memory_order_relaxed)]; }
  HandSource hand() const override { return hand_; }
  std::optional<glm::vec3> pick(const glm::vec3& origin_mm, const glm::vec3& direction) const override {
    const auto hit = wall_->tree().ray_cast(glm::dvec3(origin_mm), glm::dvec3(direction));
    if (!hit) return std::nullopt;
    return to_f(hit->point_mm);
  }

  void start() override {
    if (!real_thread_) {
      real_thread_ = std::make_unique<HapticThread>(steady_, kPeriodUs, [this](std::int64_t t) { return tick(t); });
    }
    real_thread_->start();
  }
  void stop() override {
    if (real_thread_) real_thread_->stop();
  }
  void step_virtual(std::int64_t ticks) override {
    if (!virtual_thread_) {
      virtual_thread_ =
          std::make_unique<HapticThread>(virtual_clock_, kPeriodUs, [this](std::int64_t t) { return tick(t); });
    }
    virtual_thread_->run(std::stop_token{}, virtual_thread_->ticks() + ticks);
  }
  bool over() const override { return over_.load(std::memory_order_acquire); }
  void end_run() override { end_requested_.store(true, std::memory_order_release); }
  double haptic_rate_hz() const override { return active_thread() ? active_thread()->rate_hz() : 0.0; }
  std::int64_t haptic_ticks() const override { return active_thread() ? active_thread()->ticks() : 0; }
  std::int64_t haptic_cpu_time_us() const override { return active_thread() ? active_thread()->cpu_time_us() : 0; }
  std::string haptic_scheduling() const override {
    return real_thread_ ? ThreadPriority::name(real_thread_->scheduling()) : "virtual time";
  }
  KeyboardHand& keyboard() override { return keyboard_; }
  SnapshotExchange<SceneSnapshot>& snapshots() override { return exchange_; }
  EventLog& events() override { return events_; }
  RunSummary summary() const override { return metrics_.summary(); }

 private:
  const HapticThread* active_thread() const { return real_thread_ ? real_thread_.get() : virtual_thread_.get(); }
  bool tick(std::int64_t sim_time_us);
  void switch_tool(std::int64_t sim_time_us);
  void release_box();
  void publish(std::int64_t sim_time_us);
  // printf-style line for the output panel (the implicit `this` is argument 1).
  void log(std::int64_t t, const char* fmt, ...) __attribute__((format(printf, 3, 4)));

  std::string case_name_;
  std::string vessel_file_;
  std::string device_status_;
  HandSource hand_ = HandSource::kKeyboard;
  vessel::VesselSurface surface_;
  vessel::SurfaceMesh overview_;
  std::optional<glm::vec3> target_;
  float target_radius_mm_ = 2.0F;
  tool::Case case_;
  std::unique_ptr<tool::MeshWall> wall_;
  std::unique_ptr<tool::Simulator> sim_;
  tool::Snapshot tool_snap_;
  std::vector<std::string> tool_names_;
  std::atomic<std::size_t> active_{0};

  KeyboardHand keyboard_;
  double base_insertion_mm_ = 0.0;  // the active tool's insertion when it was selected
  double base_rotation_rad_ = 0.0;
  double box_ref_insertion_mm_ = 0.0;  // the box's reading then
  double box_ref_rotation_rad_ = 0.0;
  double box_insertion_mm_ = 0.0;
  double box_rotation_rad_ = 0.0;
  std::optional<ScriptedHand> scripted_;
#if CATHBOX_TRAINER_HAS_BOX
  std::unique_ptr<BoxHand> box_;
  BoxReading last_box_;
#endif
  HandObservation seen_;
  RunMetrics metrics_;
  SnapshotExchange<SceneSnapshot> exchange_;
  EventLog events_;
  SteadyClock steady_;
  VirtualClock virtual_clock_;
  std::unique_ptr<HapticThread> real_thread_;
  std::unique_ptr<HapticThread> virtual_thread_;
  std::atomic<bool> over_{false};
  std::atomic<bool> end_requested_{false};
};

bool SimTrainerSession::load(const SessionConfig& config, std::string& error) {
  const std::filesystem::path path(config.case_path);
  if (path.extension() == ".case") {
    tool::CaseParse parsed = tool::load_case(config.case_path);
    if (!parsed.value) {
      error = parsed.error;
      return false;
    }
    case_ = std::move(*parsed.value);
  } else {  // a bare vessel file: the default guidewire from the start of the root segment
    case_.name = path.stem().string();
    case_.vessel_path = config.case_path;
    case_.tools = {tool::default_guidewire()};
  }
  case_name_ = case_.name.empty() ? path.filename().string() : case_.name;
  if (case_.vessel_path.empty()) {
    error = config.case_path + ": the trainer needs a case with a vessel file (analytic tubes have no surface to show)";
    return false;
  }
  vessel_file_ = case_.vessel_path;

  const vessel::HclmReadResult read = vessel::load_hclm(vessel_file_);
  if (!read.ok()) {
    error = read.errors.front().to_string();
    return false;
  }
  const vessel::MeshOptions options;
  surface_ = vessel::build_vessel_surface(read.model, options);
  if (!surface_.ok()) {
    error = surface_.error;
    return false;
  }
  if (surface_.mesh.triangle_count() > kOverviewTriangles && options.subdivision_level > 0) {
    vessel::MeshOptions coarse = options;
    coarse.subdivision_level = options.subdivision_level - 1;
    coarse.ring_points = 4;
    vessel::VesselSurface o = vessel::build_vessel_surface(read.model, coarse);
    if (o.ok()) overview_ = std::move(o.mesh);
  }

  // The wall the tools touch is the surface the views draw, in the collision tree.
  collision::TreeBuild tree = collision::ObbTree::build(surface_.mesh);
  if (!tree.tree) {
    error = vessel_file_ + ": " + tree.error;
    return false;
  }
  wall_ = std::make_unique<tool::MeshWall>(std::move(*tree.tree));
  const tool::Entry entry = case_.entry ? *case_.entry : root_entry(surface_.smoothed);
  sim_ = std::make_unique<tool::Simulator>(*wall_, case_.tools, entry);
  for (const tool::ToolSpec& t : case_.tools) tool_names_.push_back(t.name);
  active_.store(sim_->active_tool(), std::memory_order_relaxed);

  // The target, and the way there for the scripted hand.
  const vessel::VesselModel& model = surface_.smoothed;
  const std::vector<PathSegment> segments = path_segments(model);
  const PathPoint from = CenterlinePath::nearest(segments, to_f(entry.point_mm));
  std::optional<PathPoint> goal;
  if (case_.target) {
    const auto index = model.index_of(case_.target->segment);
    if (!index) {
      error = config.case_path + ": target segment " + std::to_string(case_.target->segment) + " is not in " + vessel_file_;
      return false;
    }
    goal = PathPoint{*index, case_.target->fraction};
    target_ = CenterlinePath::point_at(segments[*index], case_.target->fraction);
    target_radius_mm_ = static_cast<float>(std::clamp(radius_near(model, *target_), 1.5, 4.0));
  } else {
    goal = CenterlinePath::farthest_leaf(segments, from);
  }

  if (config.scripted_hand) {
    hand_ = HandSource::kScripted;
    device_status_ = "scripted hand";
    std::vector<glm::vec3> way;
    if (goal) way = CenterlinePath::between(segments, from, *goal);
    scripted_.emplace(std::move(way), sim_->rod(sim_->active_tool()).max_insertion_mm());
  } else {
    hand_ = HandSource::kKeyboard;
#if CATHBOX_TRAINER_HAS_BOX
    device_status_ = "keyboard (no box)";
    if (config.box != BoxChoice::kNone) {
      std::string box_error;
      box_ = BoxHand::connect(config.box, config.emu_socket, config.emu_program, box_error);
      if (box_) {
        hand_ = HandSource::kBox;
        device_status_ = box_->describe() + " + keyboard";
      } else {
        device_status_ = "keyboard (box: " + box_error + ")";
      }
    }
#else
    device_status_ = "keyboard (built without the device module)";
#endif
  }
  metrics_ = RunMetrics(target_, target_radius_mm_);
  exchange_.prepare_slots([](SceneSnapshot& s) { s.reserve(kMaxNodesPerTool); });
  sim_->copy_snapshot(tool_snap_);
  const tool::TipPose tip = sim_->tip(sim_->active_tool());
  seen_.tip_mm = to_f(tip.position_mm);
  seen_.tip_direction = to_f(tip.direction);
  seen_.tip_bend = to_f(tip.normal);
  publish(0);
  return true;
}

void SimTrainerSession::log(std::int64_t t, const char* fmt, ...) {
  char buf[112];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  (void)events_.push(t, buf);
}

void SimTrainerSession::release_box() {
#if CATHBOX_TRAINER_HAS_BOX
  if (box_) box_->release();
#endif
}

void SimTrainerSession::switch_tool(std::int64_t sim_time_us) {
  if (sim_->tool_count() < 2) return;
  const std::size_t next = (sim_->active_tool() + 1) % sim_->tool_count();
  sim_->select(next);
  active_.store(next, std::memory_order_relaxed);
  // The hand now holds the other tool: it carries on from where that tool is.
  base_insertion_mm_ = sim_->insertion_mm(next);
  base_rotation_rad_ = sim_->rotation_rad(next);
  box_ref_insertion_mm_ = box_insertion_mm_;
  box_ref_rotation_rad_ = box_rotation_rad_;
  keyboard_.reset(0.0, 0.0);
  log(sim_time_us, "now holding the %s", tool_names_[next].c_str());
}

bool SimTrainerSession::tick(std::int64_t sim_time_us) {
  if (over_.load(std::memory_order_acquire)) return false;  // a finished run stays as it ended
  if (end_requested_.load(std::memory_order_acquire)) {
    over_.store(true, std::memory_order_release);
    release_box();
    publish(sim_time_us);
    return false;
  }
  const double max_mm = sim_->rod(sim_->active_tool()).max_insertion_mm();
  double insertion = 0.0;
  double rotation = 0.0;
  if (scripted_) {
    const HandCommand c = scripted_->step(kDtS, seen_);
    insertion = c.insertion_mm;
    rotation = c.rotation_rad;
  } else {
    for (int n = keyboard_.take_tool_switches(); n > 0; --n) switch_tool(sim_time_us);
#if CATHBOX_TRAINER_HAS_BOX
    if (box_) {
      const BoxReading r = box_->poll();
      if (r.link_up != last_box_.link_up) log(sim_time_us, "box link %s", r.link_up ? "up" : "down");
      if (r.faults != last_box_.faults) log(sim_time_us, "box faults 0x%02x", static_cast<unsigned>(r.faults));
      last_box_ = r;
      box_insertion_mm_ = r.insertion_mm;
      box_rotation_rad_ = r.rotation_rad;
    }
#endif
    // The keyboard drives on its own, or adds to what the box measures.
    keyboard_.advance(kDtS, -max_mm, max_mm);
    insertion = std::clamp(base_insertion_mm_ + (box_insertion_mm_ - box_ref_insertion_mm_) + keyboard_.insertion_mm(),
                           0.0, max_mm);
    rotation = base_rotation_rad_ + (box_rotation_rad_ - box_ref_rotation_rad_) + keyboard_.rotation_rad();
  }
  const std::size_t tool_now = sim_->active_tool();
  sim_->set_insertion(tool_now, insertion);
  sim_->set_rotation(tool_now, rotation);
  sim_->step(kDtS);
#if CATHBOX_TRAINER_HAS_BOX
  if (box_) {
    // The law is in the simulation's insertion; the box sees it without the other terms.
    tool::ForceLaw law = sim_->force_law(tool_now);
    law.insertion0_mm -= base_insertion_mm_ - box_ref_insertion_mm_ + keyboard_.insertion_mm();
    law.rotation0_rad -= base_rotation_rad_ - box_ref_rotation_rad_ + keyboard_.rotation_rad();
    box_->send(law);
  }
#endif
  sim_->copy_snapshot(tool_snap_);
  const tool::ToolSnapshot& held = tool_snap_.tools[tool_now];
  seen_.tip_mm = to_f(held.tip.position_mm);
  seen_.tip_direction = to_f(held.tip.direction);
  seen_.tip_bend = to_f(held.tip.normal);
  seen_.hand_force_mN = held.hand_force_mN;

  TickObservation obs;
  obs.time_us = sim_time_us;
  obs.tip_mm = seen_.tip_mm;
  obs.hand_force_mN = std::abs(held.hand_force_mN);
  for (const tool::ToolSnapshot& t : tool_snap_.tools) {
    for (const tool::RodContact& c : t.contacts) obs.wall_force_mN = std::max(obs.wall_force_mN, c.normal_force_mN);
  }
  for (const tool::RodContact& c : held.contacts) {
    // The distal few nodes: the rod's node numbering ends at the tip.
    if (c.node + 3 >= sim_->rod(tool_now).node_total()) obs.tip_in_contact = true;
  }
  const int contacts_before = metrics_.summary().wall_contacts;
  metrics_.observe(obs);
  if (metrics_.summary().wall_contacts > contacts_before) {
    log(sim_time_us, "tip on the wall, segment %d (%.1f mN)", held.tip_segment, obs.wall_force_mN);
  }
  bool go_on = true;
  if (metrics_.summary().reached_target) {
    log(sim_time_us, "target reached: %.1f mm of tip travel", metrics_.summary().path_length_mm);
    go_on = false;
  }
  if (scripted_ && static_cast<double>(sim_time_us) * 1e-6 >= kScriptedLimitS) {
    log(sim_time_us, "scripted hand: time limit of %.0f s", kScriptedLimitS);
    go_on = false;
  }
  if (scripted_ && scripted_->gave_up()) {
    log(sim_time_us, "scripted hand: stuck %.0f mm along the way, gives up after %d tries", scripted_->progress_mm(),
        scripted_->retries());
    go_on = false;
  }
  // The path ends at the target, if there is one: the hand goes on until the tip is level with
  // it (a tip on the wall 1 mm short of it can be further than the lumen radius from it); to a
  // leaf's end, 1 mm short of the cap is the end.
  const double end_margin_mm = target_ ? 0.0 : 1.0;
  if (scripted_ && scripted_->path_length_mm() > 0.0 &&
      scripted_->progress_mm() >= scripted_->path_length_mm() - end_margin_mm) {
    log(sim_time_us, "scripted hand: end of the path (%.0f mm)", scripted_->path_length_mm());
    go_on = false;
  }
  if (!go_on) {
    over_.store(true, std::memory_order_release);
    release_box();
  }
  publish(sim_time_us);
  return go_on;
}

void SimTrainerSession::publish(std::int64_t sim_time_us) {
  SceneSnapshot& s = exchange_.write_slot();
  s.sim_time_us = sim_time_us;
  const std::size_t active = sim_->active_tool();
  s.tool_count = static_cast<int>(std::min<std::size_t>(tool_snap_.tools.size(), SceneSnapshot::kMaxTools));
  s.contacts.clear();
  for (int i = 0; i < s.tool_count; ++i) {
    const tool::ToolSnapshot& t = tool_snap_.tools[static_cast<std::size_t>(i)];
    ToolView& tv = s.tools[static_cast<std::size_t>(i)];
    tv.active = static_cast<std::size_t>(i) == active;
    tv.nodes_mm.clear();
    tv.frames.clear();
    const std::size_t n = std::min(t.positions_mm.size(), tv.nodes_mm.capacity());  // never allocate here
    for (std::size_t k = 0; k < n; ++k) {
      tv.nodes_mm.push_back(to_f(t.positions_mm[k]));
      tv.frames.push_back(k < t.normals.size() ? to_f(t.normals[k]) : glm::vec3(0.0F));
    }
    tv.radius_mm = t.radii_mm.empty() ? 0.2F : *std::max_element(t.radii_mm.begin(), t.radii_mm.end());
    for (const tool::RodContact& c : t.contacts) {
      if (s.contacts.size() == SceneSnapshot::kMaxContacts) break;
      s.contacts.push_back({to_f(c.point_mm), static_cast<float>(c.normal_force_mN)});
    }
  }
  if (active < tool_snap_.tools.size()) {
    const tool::ToolSnapshot& held = tool_snap_.tools[active];
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
  s.haptic_ticks = t ? t->ticks() : 0;
  s.dropped_ticks = t ? t->dropped() : 0;
  s.summary = metrics_.summary();
  s.run_over = over_.load(std::memory_order_relaxed);
  exchange_.publish();
}

}  // namespace

std::unique_ptr<TrainerSession> TrainerSession::open(const SessionConfig& config, std::string& error) {
  auto s = std::make_unique<SimTrainerSession>();
  if (!s->load(config, error)) return nullptr;
  return s;
}

}  // namespace cathbox::app
