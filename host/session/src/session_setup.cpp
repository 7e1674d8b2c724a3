// Session's construction: the simulator on the case's wall, the procedure units the case calls
// for (fluoroscopy, thrombectomy, coils, balloons), the metrics' settings and the first feedback.
#include <algorithm>

#include "scenario/case_wall.hpp"
#include "session/session.hpp"
#include "session_controls.hpp"
#include "tip_feedback.hpp"

namespace cathbox::session {

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
  exchange_.prepare_slots([this, nodes, cells](SceneSnapshot& s) {
    s.reserve(nodes);
    s.fluoro.reserve(cells, nodes);
    prepare_snapshot(s);
  });
  sim_->copy_snapshot(snap_);
  if (thrombectomy_) thrombectomy_->tick(0, snap_);  // the tips, before the first control
  // The hand sees where the tool starts before the first tick.
  HandFeedback fb;
  fb.tick = -1;
  fb.held = input_.held;
  const tool::ToolSnapshot& held = snap_.tools[input_.held];
  set_tip_feedback(fb, held);
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
    // A build that cannot mesh (the WebAssembly session) builds it on the world's surface, which
    // is the same mesh: the same wall, so that its runs replay here hash for hash.
    if (!wall && scene_->world->mesh() != nullptr) wall = tool::build_mesh_wall(*scene_->world->source_model(), *scene_->world->mesh());
    if (wall) {
      angioplasty_ = std::make_unique<tool::Angioplasty>(*scene_->world->source_model(), std::move(*wall),
                                                         tool::WallSwap::Mode::kSynchronous, tool::LumenRemodelParams{},
                                                         std::move(builder));
    }
  }
  const tool::CaseWall* compliant = scene_->spec.wall ? &*scene_->spec.wall : nullptr;
  const vessel::VesselModel* read = scene_->world->source_model();
  if (!angioplasty_) wall_field_ = tool::make_case_wall_field(compliant, scene_->world->wall(), read);
  if (wall_field_ && scene_->flow) {
    // The pulse scales every flow (flow_network.hpp), and with the terminal resistances fixed every
    // pressure above venous with it: the inlet's is the largest.
    for (std::size_t k = 0; k < scene_->flow->node_count(); ++k) {
      pulse_mean_kPa_ = std::max(pulse_mean_kPa_, 1e-3 * scene_->flow->node_pressure_Pa(static_cast<int>(k)));
    }
  }
  const tool::WallModel& wall = angioplasty_ ? angioplasty_->wall() : wall_field_ ? wall_field_->wall() : scene_->world->wall();
  sim_ = std::make_unique<tool::Simulator>(wall, tools, scene_->entry);
  tool::use_case_wall(*sim_, compliant, read);  // a compliant wall
  // The released coils' solve may run on past a tick, into the time the haptic loop waits for
  // the next: what the tick reads of them after the step is their last finished solve's
  // (Simulator::released_overlap; snapshot, metrics and state hash alike).
  sim_->set_released_overlap(true);
  if (wall_field_ && pulse_mean_kPa_ > 0.0) sim_->set_before_solves([this] { pulse_wall(); });
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

}  // namespace cathbox::session
