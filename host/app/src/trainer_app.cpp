#include "app/trainer_app.hpp"

#include <algorithm>
#include <cstdio>

#include "app/carm_panel.hpp"
#include "app/gl.hpp"
#include "app/gl_window.hpp"
#include "app/replay_panel.hpp"
#include "session/fluoro_controls.hpp"
#include "app/fluoro_frontend.hpp"
#include "app/fluoro_renderer.hpp"
#include "scenario/case_file.hpp"
#include "app/server_link.hpp"
#include "app/trainer_launch.hpp"
#include "device/gpiod_foot_pedal.hpp"
#include "app/trainer_ui.hpp"
#include "base/exit_codes.hpp"
#include "session/records_dir.hpp"
#include "vessel/hclm.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::app {

TrainerApp::TrainerApp(TrainerOptions options, std::string program_dir)
    : options_(std::move(options)), program_dir_(std::move(program_dir)) {
  settings_.wireframe = options_.wireframe;
}

TrainerApp::~TrainerApp() {
  follower_.reset();  // a wall being prepared reads the session's contrast cells
  close_live();  // stops the haptic thread, closes the record and queues it for the server
  link_.reset();  // finishes the upload in progress (bounded by its timeout)
  replay_.reset();
  replay_panel_.reset();
  ui_.reset();
  fluoro_.reset();
  renderer_.reset();
  window_.reset();
}

session::Session& TrainerApp::current() { return replay_ ? replay_->session() : *live_; }

base::Status<> TrainerApp::open_live(const std::string& case_path) {
  follower_.reset();
  shown_wall_.reset();
  close_live();
  replay_.reset();
  LiveSession live = open_live_session(options_, program_dir_, case_path, scripted_, keyboard_);
  if (!live.session) return base::Error{live.error};
  live_ = std::move(live.session);
  fluoro_switches_ = session::FluoroSwitches(foot_pedal_.get());  // a new run starts with the pedal up
  drive_ = DeviceDrive();  // and no drive running
  record_path_ = live.record_path;
  case_path_ = case_path;
  if (link_) {
    live_assignment_ = options_.assignment && link_->assignment_for(case_path) == options_.assignment
                           ? options_.assignment
                           : link_->assignment_for(case_path);
    link_->begin_run(live_->scene().name, live_assignment_, live_->tool_names());
  }
  if (!live.note.empty()) std::fprintf(stderr, "cathbox-trainer: %s\n", live.note.c_str());
  return base::Ok{};
}

base::Status<> TrainerApp::open_replay(const std::string& path) {
  close_live();  // a run being recorded is closed first (and queued for the server)
  follower_.reset();
  shown_wall_.reset();
  auto opened = session::ReplayPlayer::open(path);
  if (!opened) return base::Error{opened.error().message};
  std::unique_ptr<session::ReplayPlayer> player = std::move(*opened);
  if (player->session().scene().mesh() == nullptr) {
    return base::Error{path + ": the record's case has no vessel surface to show"};
  }
  replay_ = std::move(player);
  record_path_ = path;
  return base::Ok{};
}

int TrainerApp::run() {
  if (options_.help) {
    std::fputs(trainer_usage().c_str(), stdout);
    return base::kExitOk;
  }
  // Headless runs and benches use the autopilot unless a box was asked for (--emu, --box):
  // then the run goes through the box, in real time.
  const bool box_asked = options_.box == BoxChoice::kEmulator || !options_.boxes.empty();
  scripted_ = (options_.headless || options_.bench_seconds > 0.0) && !box_asked;
  if (options_.replay.empty() && options_.bench_seconds <= 0.0) {
    if (const int code = open_server_link(); code >= 0) return code;
  }
  if (options_.headless && options_.frames == 0 && options_.bench_seconds <= 0.0) {
    return options_.replay.empty() ? run_headless_summary() : run_headless_replay();
  }
  if (const int code = open_foot_pedal(); code >= 0) return code;
  return run_window();
}

void TrainerApp::load_scene() {
  const session::SessionCase& scene = current().scene();
  const vessel::SurfaceMesh& mesh = *scene.mesh();
  vessel::SurfaceMesh overview;
  if (mesh.triangle_count() > kOverviewTriangles) {
    const vessel::HclmReadResult read = vessel::read_hclm(scene.vessel_text, scene.vessel_file);
    if (read.ok()) overview = overview_mesh(read.model, mesh.triangle_count());
  }
  renderer_->set_vessel({mesh.positions_mm, mesh.normals, mesh.triangles},
                        {overview.positions_mm, overview.normals, overview.triangles});
  renderer_->set_target(scene.target_mm, scene.target_radius_mm);
  load_fluoro_view(scene);
  frame_camera();
  ui_->add_line("case " + scene.name + ": " + std::to_string(renderer_->detail_triangles()) + " triangles (global view " +
                std::to_string(renderer_->overview_triangles()) + "); " + (replay_ ? "replay: " : "hand: ") +
                current().hand_description());
  if (!record_path_.empty()) ui_->add_line((replay_ ? "playing " : "recording to ") + record_path_);
  if (link_) ui_->add_line(link_->status_line() + (live_assignment_ ? ", this run counts for assignment " + std::to_string(*live_assignment_) : ""));
}

void TrainerApp::load_fluoro_view(const session::SessionCase& scene) {
  // The case's fluoroscopy statements: `realistic` (no 3D view) and its working projections.
  bool realistic = false;
  std::vector<flow::NamedProjection> views;
  if (!scene.case_text.empty()) {
    if (const tool::CaseParse c = tool::parse_case(scene.case_text, scene.case_file)) {
      realistic = c->realistic;
      views = c->views;
    }
  }
  const bool fluoro = options_.view ? *options_.view == MainView::kFluoro : realistic;
  if (!fluoro) {
    fluoro_.reset();
    return;
  }
  if (!fluoro_) {
    fluoro_ = std::make_unique<FluoroRenderer>();
    if (base::Status<> ready = fluoro_->init(); !ready) {
      ui_->add_line("fluoroscopy: " + ready.error().message + "; showing the 3D view");
      fluoro_.reset();
      return;
    }
    // A window a trainee looks at: a C-arm move shows the last image while the new view is
    // projected; headless runs (screenshots) draw every frame from its own inputs.
    fluoro_->set_background_projection(!options_.headless);
  }
  // No C-arm controls yet: the case's first working projection (else AP), the isocentre on the
  // case's target, where the navigation ends.
  fluoro_settings_.pose = {};
  fluoro_inputs_ = {};
  const InjectionSettings injection = carm_panel_.injection();  // kept from case to case
  carm_panel_ = CArmPanelModel(views);
  (void)carm_panel_.set_injection(injection);
  if (!views.empty()) {
    fluoro_settings_.pose.lao_deg = views.front().lao_deg;
    fluoro_settings_.pose.cranial_deg = views.front().cranial_deg;
  }
  if (scene.target_mm) fluoro_settings_.pose.isocenter_mm = glm::dvec3(*scene.target_mm);
  // The session's contrast cells on the case's surface one level coarser than the collision
  // surface (fluoro_surface_options), or on the case's own surface as it is: the lumen takes
  // their iodine.
  if (const session::FluoroUnit* unit = current().fluoro(); unit != nullptr && scene.mesh() != nullptr) {
    fluoro_mesh_ = scene.model() != nullptr && !scene.surface_given() ? fluoro_surface(*scene.model()) : vessel::SurfaceMesh{};
    fluoro_vessel_ = FluoroVessel::build(fluoro_mesh_.triangle_count() > 0 ? fluoro_mesh_ : *scene.mesh(), unit->transport());
    fluoro_->set_vessel(fluoro_vessel_);
  }
  fluoro_settings_.patient_transmission = flow::HeadPhantom::neuro().central_transmission(flow::CArm(fluoro_settings_.pose));
  ui_->add_line("fluoroscopy: " + (views.empty() ? std::string("AP") : views.front().name) +
                (scene.target_mm ? ", isocentre on the target" : ""));
  // The autopilot (headless frames, bench) has no foot: it holds the pedal down, so the demo
  // shows live fluoroscopy. A trainee presses it (Space, the GPIO pedal); a script says when.
  if (scripted_ && options_.script.empty() && !replay_ && current().fluoro() != nullptr) {
    (void)current().post(session::fluoro_control::pedal(true));
    ui_->add_line("fluoroscopy: the autopilot holds the pedal down");
  }
}

void TrainerApp::follow_wall(const session::Session& s, std::uint64_t generation, double wall_pressure_kPa, bool wait) {
  const session::FluoroUnit* unit = fluoro_ ? s.fluoro() : nullptr;
  std::optional<VesselFollower::Prepared> next =
      follower_.poll(generation, wall_pressure_kPa, s, unit ? &unit->transport() : nullptr, wait);
  if (!next) return;
  renderer_->upload_vessel(next->scene);
  if (fluoro_ && next->fluoro) {
    fluoro_->upload_vessel(std::move(*next->fluoro));
    fluoro_vessel_ = std::move(*next->fluoro_vessel);
  }
  const bool widened = !shown_wall_ || shown_wall_->generation != next->generation;
  shown_wall_ = std::make_unique<VesselFollower::Prepared>(std::move(*next));  // the views point into it
  if (widened && shown_wall_->generation > 0) {
    ui_->add_line("vessel wall " + std::to_string(shown_wall_->generation) + ": the widened lumen is shown");
  }
}

void TrainerApp::frame_camera() {
  const vessel::SurfaceMesh& mesh = *current().scene().mesh();
  glm::vec3 lo(1e30F);
  glm::vec3 hi(-1e30F);
  for (const glm::vec3& p : mesh.positions_mm) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  if (mesh.positions_mm.empty()) lo = hi = glm::vec3(0.0F);
  camera_.frame(lo, hi);
}

int TrainerApp::open_foot_pedal() {
  if (options_.pedal_gpio.empty()) return -1;
  const device::Result<device::PedalConfig> config = device::PedalConfig::parse(options_.pedal_gpio);
  if (!config) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", config.error().message.c_str());
    return base::kExitBadInput;
  }
  auto pedal = device::GpiodFootPedal::open(*config);
  if (!pedal) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", pedal.error().message.c_str());
    return base::kExitNoDevice;
  }
  foot_pedal_ = std::move(*pedal);
  return -1;
}

// The window, its renderers and UI, and the run (live or the --replay record) opened in it:
// kExitOk, or the exit code with its line printed.
int TrainerApp::open_window(const std::string& case_path) {
  base::Result<std::unique_ptr<GlWindow>> window =
      GlWindow::create(options_.width, options_.height, "Cathbox trainer", !options_.headless);
  if (!window) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", window.error().message.c_str());
    return base::kExitNoDisplay;
  }
  window_ = std::move(*window);
  window_->set_vsync(!options_.headless && options_.bench_seconds <= 0.0);
  renderer_ = std::make_unique<SceneRenderer>();
  ui_ = std::make_unique<TrainerUi>();
  if (base::Status<> ready = renderer_->init(); !ready) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", ready.error().message.c_str());
    return base::kExitNoDisplay;
  }
  if (!ui_->init(window_->handle())) {
    std::fprintf(stderr, "cathbox-trainer: cannot initialise the UI\n");
    return base::kExitNoDisplay;
  }
  if (options_.picker) ui_->open_picker();
  const std::string records = options_.records_dir.empty() ? session::records_dir() : options_.records_dir;
  replay_panel_ = std::make_unique<ReplayPanel>(records);
  const base::Status<> opened = options_.replay.empty() ? open_live(case_path) : open_replay(options_.replay);
  if (!opened) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", opened.error().message.c_str());
    return base::kExitBadInput;
  }
  load_scene();
  return base::kExitOk;
}

// The main view: the fluoroscopic image (its inputs change with each pulse) or the 3D scene.
void TrainerApp::render_main_view(const ScreenLayout& layout, int fh, const session::SceneSnapshot& snap) {
  if (fluoro_) {
    // A pulse's image shows what was there when it fired: the inputs change with the pulse.
    if (FluoroInputs next = fluoro_inputs_from_snapshot(snap, fluoro_settings_);
        next.image.pulse != fluoro_inputs_.image.pulse || next.image.beam_on != fluoro_inputs_.image.beam_on ||
        next.image.roadmap_pulse != fluoro_inputs_.image.roadmap_pulse || !(next.pose == fluoro_inputs_.pose)) {
      fluoro_inputs_ = std::move(next);
    }
    if (std::string e = fluoro_->render(layout.global, fh, fluoro_inputs_); !e.empty() && e != fluoro_error_) {
      ui_->add_line("fluoroscopy: " + e);  // once per distinct error
      fluoro_error_ = e;
    }
  } else {
    renderer_->render_global(layout.global, fh, camera_.view(), camera_.projection(layout.global.aspect()), settings_);
  }
}

// What the trainee asked of the live run this frame: end it, switch tool, detach or load a
// coil, aspiration and balloon guide, the C-arm panel's controls and the fluoroscopy switches.
void TrainerApp::post_live_actions(const UiActions& act, const InputActions& input, const CArmPanelActions& carm_act,
                                   const session::SceneSnapshot& snap, std::int64_t now) {
  if (act.end_run) live_->end_run();
  if (act.switch_tool || input.switch_tool) (void)live_->post(session::Control::select_next_tool());
  // The session refuses (and logs why) a detach or load on a tool that carries no coil.
  if (input.detach_coil) (void)live_->post(session::Control::detach_coil(live_->held_tool()));
  if (input.load_coil) (void)live_->post(session::Control::load_coil(live_->held_tool()));
  // Thrombectomy: V toggles the aspiration catheter's vacuum, B the balloon guide (the case's
  // first of each, whichever tool is held; the session refuses and logs what does not apply).
  if (input.aspiration && snap.aspiration_tool >= 0) {
    (void)live_->post(session::Control::aspiration(static_cast<std::size_t>(snap.aspiration_tool), !snap.aspirating));
  }
  if (input.balloon_guide && snap.balloon_guide_tool >= 0) {
    (void)live_->post(session::Control::balloon_guide(static_cast<std::size_t>(snap.balloon_guide_tool), !snap.flow_arrest));
  }
  // U / E: the stent's unsheathing and retrieval drives set the keyboard hand's speed over the
  // keys' own (set in InputController::handle) while one runs; refused while a box holds the hand.
  const DriveKeys keys{input.unsheathe, input.retrieve, input.steering || input.switch_tool || act.switch_tool,
                       live_->hand_kind() == session::HandKind::kBox};
  const DriveCommand drive = drive_.update(keys, snap);
  if (drive.select) (void)live_->post(session::Control::select_tool(*drive.select));
  if (drive.driving) keyboard_.set_speeds(drive.insert_mm_s, 0.0);
  if (!drive.note.empty()) ui_->add_line(drive.note);
  for (const session::Control& c : carm_act.controls) (void)live_->post(c);
  const InjectionSettings& inj = carm_panel_.injection();  // the I key injects what the panel says
  fluoro_switches_.set_injection(inj.volume_ml, inj.rate_ml_s, inj.concentration_mgI_ml);
  fluoro_switches_.update(input.fluoro, static_cast<std::uint64_t>(now), [this](const session::Control& c) { return live_->post(c); },
                          snap.fluoro.available ? &snap.fluoro.pose : nullptr);
}

// Another record to replay, or a live run (restarted, another case, back from a replay), as
// asked; false when not even the previous case opens again.
bool TrainerApp::switch_run(const UiActions& act, const ReplayPanelActions& replay_act, const std::string& chosen_path,
                            bool virtual_time) {
  std::string next_replay = replay_act.open;
  if (act.replay_this_run && !record_path_.empty()) next_replay = record_path_;
  if (!next_replay.empty()) {
    if (const base::Status<> replaying = open_replay(next_replay); replaying) {
      load_scene();
      replay_->play();
    } else {
      ui_->add_line("cannot replay " + next_replay + ": " + replaying.error().message);
      if (!replay_ && !live_ && !open_live(case_path_.empty() ? chosen_path : case_path_)) return false;
    }
  } else if (replay_act.back_to_live || (live_ && (act.restart || act.pick_case >= 0))) {
    const int pick_index = act.pick_case >= 0 ? act.pick_case : current_case_;
    const std::string fallback = case_path_.empty() ? chosen_path : case_path_;
    const std::string path = pick_index >= 0 ? catalog_.entries()[static_cast<std::size_t>(pick_index)].path : fallback;
    if (const base::Status<> picked = open_live(path); picked) {
      current_case_ = pick_index;
    } else {
      ui_->add_line("cannot open " + path + ": " + picked.error().message);
      if (!open_live(fallback)) return false;
    }
    load_scene();
    if (!virtual_time) live_->start();
  }
  return true;
}

// What the HUD shows of the run.
UiStatus TrainerApp::ui_status(session::Session& s, const session::SceneSnapshot& snap, double fps) const {
  return UiStatus{fps,
                  s.hand_description(),
                  s.scene().name,
                  s.tool_names()[snap.held_tool],
                  replay_ != nullptr,
                  record_path_,
                  snap.held_coil_attached && !snap.held_coil_parting,
                  snap.held_coil_parting,
                  snap.held_next_coil,
                  snap.aspiration_tool < 0 ? -1 : (snap.aspirating ? 1 : 0),
                  snap.balloon_guide_tool < 0 ? -1 : (snap.flow_arrest ? 1 : 0),
                  replay_ ? std::vector<std::string>{} : drive_.hints(snap, s.tool_names())};
}

// The C-arm panel (fluoroscopic view) takes the top of the output panel's area, which
// `ui_layout` then leaves to the other panels.
CArmPanelActions TrainerApp::draw_carm(const ScreenLayout& layout, const session::SceneSnapshot& snap, ScreenLayout& ui_layout) {
  CArmPanelActions carm_act;
  if (fluoro_ && snap.fluoro.available) {
    const int ph = std::min(kCArmPanelHeight, layout.output.height / 2 + kCArmPanelHeight / 2);
    carm_act = draw_carm_panel({layout.output.x, layout.output.y, layout.output.width, ph}, carm_panel_, snap.fluoro, live_ != nullptr);
    ui_layout.output.y += ph;
    ui_layout.output.height = std::max(1, ui_layout.output.height - ph);
  }
  return carm_act;
}

}  // namespace cathbox::app
