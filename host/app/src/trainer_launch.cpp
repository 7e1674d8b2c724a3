#include "app/trainer_launch.hpp"

#include <filesystem>

#include "session/action_script_hand.hpp"
#include "session/box_hand.hpp"
#include "session/multi_box_hand.hpp"
#include "session/keyboard_hand.hpp"
#include "session/records_dir.hpp"
#include "session/scripted_hand.hpp"

namespace cathbox::app {
namespace {

const std::vector<std::string> kCaseExtensions = {".case", ".hclm"};
constexpr const char* kDefaultCase = "neuro_right_ica.case";
constexpr const char* kPreferredCase = "neuro";

// A box per tool (`--box TOOL=WHERE`, repeated); if one cannot be had, the keyboard, saying why
// (as for one box).
std::unique_ptr<session::Hand> rig_or_keyboard(const std::vector<std::string>& boxes, const std::string& program_dir,
                                               const session::SessionCase& scene, session::KeyboardInput& keyboard,
                                               double dt_s) {
  std::vector<session::BoxBinding> bindings;
  for (const std::string& b : boxes) {
    const base::Result<session::BoxBinding> parsed = session::parse_box_binding(b, scene.spec.tools);
    if (!parsed) return std::make_unique<session::KeyboardHand>(keyboard, dt_s, "keyboard (boxes: " + parsed.error().message + ")");
    bindings.push_back(*parsed);
  }
  session::BoxHandOptions rig_options;
  rig_options.emu_program = program_dir + "/cathbox-emu";
  rig_options.keyboard = &keyboard;
  rig_options.dt_s = dt_s;
  base::Result<std::unique_ptr<session::MultiBoxHand>> rig =
      session::MultiBoxHand::connect(bindings, rig_options, scene.spec.tools.size());
  if (!rig) return std::make_unique<session::KeyboardHand>(keyboard, dt_s, "keyboard (boxes: " + rig.error().message + ")");
  return std::move(*rig);
}

// The one box the options name (the first found, or the emulator); if there is none, the
// keyboard, saying why.
std::unique_ptr<session::Hand> box_or_keyboard(const TrainerOptions& options, const std::string& program_dir,
                                               session::KeyboardInput& keyboard, double dt_s) {
  session::BoxHandOptions box;
  box.source = options.box == BoxChoice::kAuto ? session::BoxSource::kAuto : session::BoxSource::kEmulator;
  box.emu_socket = options.emu_socket;
  box.emu_program = program_dir + "/cathbox-emu";
  box.keyboard = &keyboard;
  box.dt_s = dt_s;
  base::Result<std::unique_ptr<session::BoxHand>> connected = session::BoxHand::connect(box);
  if (!connected) return std::make_unique<session::KeyboardHand>(keyboard, dt_s, "keyboard (box: " + connected.error().message + ")");
  return std::move(*connected);
}

}  // namespace

CaseChoice choose_case(const TrainerOptions& options, const std::string& program_dir, CaseCatalog& catalog) {
  CaseChoice c;
  std::string dir = options.cases_dir;
  if (dir.empty()) {
    for (const std::string& candidate :
         {program_dir + "/../share/cathbox/cases", std::string(CATHBOX_CASES_DIR), program_dir + "/../../../cases",
          std::string("cases")}) {
      if (std::filesystem::is_directory(candidate)) {
        dir = candidate;
        break;
      }
    }
  }
  // An unreadable folder lists nothing: a case given by path still runs, else its error is the choice's.
  base::Result<CaseCatalog> scanned = CaseCatalog::scan(dir, kCaseExtensions);
  catalog = scanned ? std::move(*scanned) : CaseCatalog{};
  const std::string scan_error = scanned ? std::string() : scanned.error().message;
  if (!options.case_path.empty()) {
    const std::string name = std::filesystem::path(options.case_path).filename().string();
    for (std::size_t i = 0; i < catalog.entries().size(); ++i) {
      if (catalog.entries()[i].name == name) c.catalog_index = static_cast<int>(i);
    }
    if (c.catalog_index < 0) c.catalog_index = catalog.index_of_path(options.case_path);
    c.path = options.case_path;
    return c;
  }
  // The default: the single-wire neuro case with a target (the scripted hand reaches it), else
  // another neuro case file, else the neuro vessel file itself.
  for (std::size_t i = 0; i < catalog.entries().size(); ++i) {
    if (catalog.entries()[i].name == kDefaultCase) c.catalog_index = static_cast<int>(i);
  }
  if (c.catalog_index < 0) c.catalog_index = catalog.default_index(kPreferredCase, ".case");
  if (c.catalog_index < 0) {
    c.error = scan_error.empty() ? dir + ": no case files (.case, .hclm)" : scan_error;
    return c;
  }
  c.path = catalog.entries()[static_cast<std::size_t>(c.catalog_index)].path;
  return c;
}

LiveSession open_live_session(const TrainerOptions& options, const std::string& program_dir,
                              const std::string& case_path, bool scripted, session::KeyboardInput& keyboard) {
  LiveSession live;
  session::SessionCaseLoad scene = session::load_session_case(case_path);
  if (!scene) {
    live.error = scene.error().message;
    return live;
  }
  if (scene.value()->mesh() == nullptr) {
    live.error = case_path + ": the trainer needs a case with a vessel file (analytic tubes have no surface to show)";
    return live;
  }
  const session::SessionOptions session_options;
  const double dt_s = static_cast<double>(session_options.period_us) * 1e-6;
  std::unique_ptr<session::Hand> hand;
  if (!options.script.empty()) {
    // The same script player as `cathbox session run --script`, imaging verbs included.
    base::Result<std::unique_ptr<session::ActionScriptHand>> loaded = session::ActionScriptHand::load(options.script, *scene.value());
    if (!loaded) {
      live.error = loaded.error().message;
      return live;
    }
    hand = std::move(*loaded);
  } else if (scripted) {
    // Its insertion limit follows the held tool's (TickInput::max_insertion_um).
    session::ScriptedHandSettings autopilot_settings;
    autopilot_settings.end_margin_mm = scene.value()->target_mm ? 0.0 : 1.0;
    auto autopilot = std::make_unique<session::ScriptedHand>(
        scene.value()->route_mm, scene.value()->spec.tools.front().length_mm(), autopilot_settings);
    autopilot->set_tick_s(dt_s);
    hand = std::move(autopilot);
  } else if (!options.boxes.empty()) {
    hand = rig_or_keyboard(options.boxes, program_dir, *scene.value(), keyboard, dt_s);
  } else if (options.box == BoxChoice::kNone) {
    hand = std::make_unique<session::KeyboardHand>(keyboard, dt_s, "keyboard (no box)");
  } else {
    hand = box_or_keyboard(options, program_dir, keyboard, dt_s);
  }
  live.session = std::make_unique<session::Session>(std::move(scene.value()), std::move(hand), session_options);
  if (options.record) {
    const std::string dir = options.records_dir.empty() ? session::records_dir() : options.records_dir;
    const base::Result<std::string> path = session::new_record_path(dir, live.session->scene().name);
    if (!path) {
      live.note = "not recording: " + path.error().message;
    } else if (base::Status<> recording = live.session->record_to(*path); recording) {
      live.record_path = *path;
    } else {
      live.note = "not recording: " + recording.error().message;
    }
  }
  return live;
}

}  // namespace cathbox::app
