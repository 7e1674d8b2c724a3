#include "wasm/browser_session.hpp"

#include <cstdio>

#include "scenario/case_file.hpp"
#include "session/keyboard_hand.hpp"
#include "session/metrics.hpp"
#include "session/record_format.hpp"
#include "wasm/law_tap_hand.hpp"
#include "wasm/surface_file.hpp"

namespace cathbox::wasm {

namespace {

constexpr double kTickS = 0.001;  // SessionOptions' default period (1 kHz)

// JSON string contents: the case names and the writer's lines are plain text, quoted safely.
std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char esc[8];
      std::snprintf(esc, sizeof esc, "\\u%04x", c);
      out += esc;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

std::string metrics_json(const session::Metrics& metrics) {
  std::string out = "{";
  for (const session::NamedMetric& m : session::named_metrics(metrics)) {
    out += (out.size() > 1 ? "," : "") + quoted(m.name) + ":" + number(m.value);
  }
  return out + "}";
}

// The case's working projections (its `view` statements), as cathbox-trainer offers them.
std::vector<flow::NamedProjection> case_views(const session::SessionCase& scene) {
  if (scene.case_text.empty()) return {};
  const tool::CaseParse c = tool::parse_case(scene.case_text, scene.case_file);
  return c ? c->views : std::vector<flow::NamedProjection>{};
}

// An edit's answer for the page: 1 posted, 0 nothing to change, -1 refused (the model's line).
int posted(const std::optional<session::Control>& control, const std::string& error, session::Session& session) {
  if (control) return session.post(*control) ? 1 : -1;
  return error.empty() ? 0 : -1;
}

}  // namespace

base::Result<std::unique_ptr<BrowserSession>> BrowserSession::open(const std::string& case_path,
                                                                   const std::string& mesh_path,
                                                                   const std::string& record_path) {
  base::Result<vessel::SurfaceMesh> surface = read_surface_file(mesh_path);
  if (!surface) return surface.error();
  session::SessionCaseLoad scene = session::load_session_case(case_path, &*surface);
  if (!scene) return scene.error();
  std::unique_ptr<BrowserSession> b(new BrowserSession());
  auto hand = std::make_unique<LawTapHand>(std::make_unique<session::KeyboardHand>(b->keyboard_, kTickS, "keyboard (browser)"));
  b->hand_ = hand.get();
  b->carm_ = app::CArmPanelModel(case_views(*scene.value()));
  b->session_ = std::make_unique<session::Session>(std::move(scene.value()), std::move(hand));
  if (base::Status<> recording = b->session_->record_to(record_path); !recording) return recording.error();
  return b;
}

// Layout (floats): tick, sim time s, insertion mm, rotation rad, hand force mN, hand torque mN·mm,
// wall force mN, tip x y z, held tool, run over, tool count, contact count; then per tool: node
// count, active, nodes x y z...; then per contact: x y z force mN.
std::size_t BrowserSession::pack_snapshot() {
  auto& exchange = session_->snapshots();
  exchange.acquire();
  const session::SceneSnapshot& s = exchange.read_slot();
  packed_.clear();
  const std::size_t contacts = s.contacts.size();
  packed_.insert(packed_.end(), {static_cast<float>(s.tick), static_cast<float>(static_cast<double>(s.sim_time_us) * 1e-6),
                                 static_cast<float>(s.insertion_mm), static_cast<float>(s.rotation_rad),
                                 static_cast<float>(s.hand_force_mN), static_cast<float>(s.hand_torque_mNmm),
                                 static_cast<float>(s.wall_force_mN), s.tip_mm.x, s.tip_mm.y, s.tip_mm.z,
                                 static_cast<float>(s.held_tool), s.run_over ? 1.0F : 0.0F,
                                 static_cast<float>(s.tool_count), static_cast<float>(contacts)});
  for (int t = 0; t < s.tool_count; ++t) {
    const session::ToolView& tool = s.tools[static_cast<std::size_t>(t)];
    packed_.push_back(static_cast<float>(tool.nodes_mm.size()));
    packed_.push_back(tool.active ? 1.0F : 0.0F);
    for (const glm::vec3& p : tool.nodes_mm) packed_.insert(packed_.end(), {p.x, p.y, p.z});
  }
  for (const session::ContactView& c : s.contacts) packed_.insert(packed_.end(), {c.point_mm.x, c.point_mm.y, c.point_mm.z, c.force_mN});
  return packed_.size();
}

bool BrowserSession::tick(double insert_mm_s, double rotate_rad_s, bool steering, bool box) {
  auto& exchange = session_->snapshots();
  exchange.acquire();
  app::DriveKeys keys = pressed_;
  pressed_ = {};
  keys.cancel = keys.cancel || steering;
  keys.box = box;
  const app::DriveCommand drive = drive_.update(keys, exchange.read_slot());
  if (drive.select) (void)session_->post(session::Control::select_tool(*drive.select));
  if (!drive.note.empty()) drive_notes_.push_back(drive.note);
  if (drive.driving) {
    insert_mm_s = drive.insert_mm_s;
    rotate_rad_s = 0.0;
  }
  keyboard_.set_speeds(insert_mm_s, rotate_rad_s);
  return session_->step_virtual(1) == 1 && !session_->over();
}

std::string BrowserSession::drive_json() {
  std::string out = "{\"hints\":[";
  const std::vector<std::string> hints = drive_.hints(session_->snapshots().read_slot(), session_->tool_names());
  for (std::size_t i = 0; i < hints.size(); ++i) out += (i ? "," : "") + quoted(hints[i]);
  out += "],\"notes\":[";
  for (std::size_t i = 0; i < drive_notes_.size(); ++i) out += (i ? "," : "") + quoted(drive_notes_[i]);
  drive_notes_.clear();
  return out + "]}";
}

void BrowserSession::fluoro_keys(int bits) {
  const auto on = [bits](int k) { return (bits & (1 << k)) != 0; };
  const session::FluoroKeys keys{on(0), on(1), on(2), on(3), on(4), on(5), on(6), on(7)};
  const session::SceneSnapshot& s = session_->snapshots().read_slot();
  const flow::CArmPose* carm = s.fluoro.available ? &s.fluoro.pose : nullptr;
  switches_.update(keys, static_cast<std::uint64_t>(s.sim_time_us), [this](const session::Control& c) { return session_->post(c); },
                   carm);
}

std::string BrowserSession::carm_projections_json() const {
  std::string out = "[";
  for (const flow::NamedProjection& p : carm_.projections()) {
    out += (out.size() > 1 ? "," : "") + std::string("{\"name\":") + quoted(p.name) + ",\"lao\":" + number(p.lao_deg) +
           ",\"cranial\":" + number(p.cranial_deg) + "}";
  }
  return out + "]";
}

// The panel edits from where the C-arm is now (the native panel syncs once a frame); false
// without a fluoroscopy unit.
bool BrowserSession::carm_sync() {
  const session::SceneSnapshot& s = session_->snapshots().read_slot();
  if (s.fluoro.available) carm_.sync(s.fluoro.pose, s.fluoro.pulse_rate_hz);
  return s.fluoro.available;
}

int BrowserSession::carm_angles(double lao_deg, double cranial_deg) {
  return carm_sync() ? posted(carm_.set_angles(lao_deg, cranial_deg), carm_.error(), *session_) : 0;
}

int BrowserSession::carm_geometry(double sid_mm, double table_height_mm, double fov_mm, double collimation) {
  return carm_sync() ? posted(carm_.set_geometry(sid_mm, table_height_mm, fov_mm, collimation), carm_.error(), *session_) : 0;
}

int BrowserSession::carm_pulse_rate(double per_s) {
  return carm_sync() ? posted(carm_.set_pulse_rate(per_s), carm_.error(), *session_) : 0;
}

const std::array<double, 9>& BrowserSession::carm_state() {
  const session::SceneSnapshot& s = session_->snapshots().read_slot();
  carm_state_ = {};
  if (!s.fluoro.available) return carm_state_;
  const flow::CArmPose& p = s.fluoro.pose;
  const flow::CArm carm(p);
  carm_state_ = {p.lao_deg, p.cranial_deg, p.sid_mm, p.table_height_mm, p.fov_mm, p.collimation, s.fluoro.pulse_rate_hz,
                 s.fluoro.image.beam_on ? 1.0 : 0.0, carm.magnification(carm.isocenter_mm())};
  return carm_state_;
}

const BrowserFluoro& BrowserSession::fluoro_frame(int width, int height) {
  fluoro_.frame(session_->snapshots().read_slot(), width, height);
  return fluoro_;
}

const FluoroImage* BrowserSession::fluoro_request(int width, int height) {
  if (!fluoro_thread_) fluoro_thread_ = std::make_unique<FluoroThread>(fluoro_);
  fluoro_thread_->request(session_->snapshots().read_slot(), width, height);
  return fluoro_thread_->take();
}

cbx_command_report BrowserSession::box_command(double box_offset_mm, double box_offset_rad, const BoxReading& reading) {
  return box_law_.command(hand_->law(), box_offset_mm, box_offset_rad, reading);
}

std::string BrowserSession::snapshot_metrics_json() const {
  return metrics_json(session_->snapshots().read_slot().metrics);
}

base::Status<> BrowserSession::close_record() {
  session::Recorder* rec = session_->recorder();
  if (rec == nullptr) return base::Ok{};
  const bool ok = rec->close();
  record_bytes_ = rec->bytes_written();
  if (!ok) return base::Error{rec->error()};
  return base::Ok{};
}

std::string BrowserSession::summary_json() const {
  const session::SessionCase& scene = session_->scene();
  std::string out = "{\"case\":" + quoted(scene.name) + ",\"hand\":" + quoted(session_->hand_description()) +
                    ",\"end\":" + quoted(session::record::end_reason_name(session_->end_reason())) +
                    ",\"ticks\":" + std::to_string(session_->ticks()) + ",\"record_bytes\":" + std::to_string(record_bytes_) +
                    ",\"tools\":[";
  for (std::size_t i = 0; i < session_->tool_names().size(); ++i) out += (i ? "," : "") + quoted(session_->tool_names()[i]);
  // The case's `realistic` statement: the native trainer then opens in fluoroscopy.
  bool realistic = false;
  if (!scene.case_text.empty()) {
    if (const tool::CaseParse c = tool::parse_case(scene.case_text, scene.case_file)) realistic = c->realistic;
  }
  out += std::string("],\"realistic\":") + (realistic ? "true" : "false") + ",\"target\":";
  if (scene.target_mm) {
    out += "[" + number(scene.target_mm->x) + "," + number(scene.target_mm->y) + "," + number(scene.target_mm->z) + "," +
           number(scene.target_radius_mm) + "]";
  } else {
    out += "null";
  }
  return out + ",\"metrics\":" + metrics_json(session_->metrics()) + "}";
}

}  // namespace cathbox::wasm
