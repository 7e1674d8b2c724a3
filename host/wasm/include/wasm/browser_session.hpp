#pragma once
// The trainee page's session (host/server/web/train.html): one case run by the keyboard in a
// dedicated Web Worker, which owns the clock and calls step() as its 1 kHz pacer says
// (train_worker.js). The same Session, KeyboardHand and Recorder as cathbox-trainer's keyboard
// run; the record is a file in the module's memory file system, uploaded by the page.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "app/carm_panel_model.hpp"
#include "app/device_drive.hpp"
#include "base/result.hpp"
#include "protocol/cbx_command_report.h"
#include "session/keyboard_input.hpp"
#include "session/fluoro_switches.hpp"
#include "session/session.hpp"
#include "wasm/browser_fluoro.hpp"
#include "wasm/browser_box_law.hpp"
#include "wasm/fluoro_thread.hpp"

namespace cathbox::wasm {

class LawTapHand;

class BrowserSession {
 public:
  // The case file (its HCLM beside it), the CBXMESH2 surface file, the record to write; or one
  // line ("FILE: what").
  [[nodiscard]] static base::Result<std::unique_ptr<BrowserSession>> open(const std::string& case_path,
                                                                          const std::string& mesh_path,
                                                                          const std::string& record_path);

  // Tab: the next tool (it also stops a stent drive, as in cathbox-trainer).
  void next_tool() {
    (void)session_->post(session::Control::select_next_tool());
    pressed_.cancel = true;
  }
  void end_run() { session_->end_run(); }
  // The worker's real clock dropped ticks: its total so far (session::Session::note_paced_drops).
  void note_dropped(std::int64_t total) { session_->note_paced_drops(total); }
  // U or E pressed on the page: taken by the next tick's app::DeviceDrive (host/app
  // device_drive.hpp, cathbox-trainer's own: U unsheathes the stent, E retrieves it).
  void drive_keys(bool unsheathe, bool retrieve) {
    pressed_.unsheathe = pressed_.unsheathe || unsheathe;
    pressed_.retrieve = pressed_.retrieve || retrieve;
  }
  // One tick of the session's virtual clock (the worker's pacer decides when) with the keys held
  // now, as the native trainer maps them (host/app input_controller.cpp): mm/s, rad/s; `steering`
  // an arrow or WASD key held (it stops a drive); `box` a box drives the tools (U and E refused).
  // The stent's drive decides first, from the newest snapshot, and while it runs its speed
  // replaces the keys' (cathbox-trainer decides once a frame, the page once a tick). False once
  // the run is over.
  bool tick(double insert_mm_s, double rotate_rad_s, bool steering, bool box);
  // The drive's HUD lines (DeviceDrive::hints) and its notes since the last call (a drive stopped
  // or refused), {"hints":[...],"notes":[...]}.
  [[nodiscard]] std::string drive_json();
  [[nodiscard]] bool over() const { return session_->over(); }
  [[nodiscard]] std::int64_t ticks() const { return session_->ticks(); }

  // The newest snapshot flattened for the page (layout in browser_session.cpp); its size in floats.
  std::size_t pack_snapshot();
  [[nodiscard]] const float* packed() const { return packed_.data(); }
  // The packed snapshot's metrics, {name: value} (session::named_metrics): the live frame's.
  [[nodiscard]] std::string snapshot_metrics_json() const;
  // Once over: the record closed, or the writer's line.
  [[nodiscard]] base::Status<> close_record();
  // {"case", "hand", "end", "ticks", "record_bytes", "target":[x,y,z,r]|null, "metrics":{name:value}}
  [[nodiscard]] std::string summary_json() const;

  // The fluoroscopy keys held (the native trainer's: Space pedal, I inject, R roadmap, X clear it,
  // [ ] - = the C-arm), as bits in that order: their controls posted on each change
  // (session::FluoroSwitches, as cathbox-trainer does once a frame).
  void fluoro_keys(int bits);
  // The fluoroscopic image's inputs for the page (wasm/browser_fluoro.hpp), from the snapshot
  // pack_snapshot() took; open_fluoro() false: the case has no fluoroscopy unit.
  bool open_fluoro() { return fluoro_.open(*session_); }
  const BrowserFluoro& fluoro_frame(int width, int height);
  // The same made off the caller's thread (wasm/fluoro_thread.hpp, started by the first call):
  // the snapshot pack_snapshot() took handed over, the newest image made returned (null until
  // one is). The haptic worker's real clock uses this, so that no tick waits for an image.
  const FluoroImage* fluoro_request(int width, int height);
  // The image whose arrays the page is sent: the thread's once it runs, else fluoro_frame()'s.
  [[nodiscard]] const FluoroImage& fluoro_image() const { return fluoro_thread_ ? fluoro_thread_->shown() : fluoro_.image(); }
  // The C-arm panel: the native trainer's panel model (app::CArmPanelModel) synced to the
  // snapshot's C-arm before each edit. The projections offered (the standard ones, then the
  // case's working views) as JSON [{"name","lao","cranial"}]; an edit returns 1 (its control
  // posted: recorded, replayed), 0 (nothing changes) or -1 (refused: carm_error() names the field
  // and its range).
  [[nodiscard]] std::string carm_projections_json() const;
  int carm_angles(double lao_deg, double cranial_deg);
  int carm_geometry(double sid_mm, double table_height_mm, double fov_mm, double collimation);
  int carm_pulse_rate(double per_s);
  [[nodiscard]] const std::string& carm_error() const { return carm_.error(); }
  // The C-arm now (the packed snapshot's): LAO, cranial (deg), SID, table height, field of view
  // (mm), collimation, pulses per s, beam on (1/0), magnification at the isocentre; zeros without
  // a fluoroscopy unit.
  [[nodiscard]] const std::array<double, 9>& carm_state();
  [[nodiscard]] const BrowserFluoro& fluoro() const { return fluoro_; }

  // The box's command for the held tool's newest law (wasm/browser_box_law.hpp).
  void configure_box(const BoxLawConfig& config) { box_law_.configure(config); }
  [[nodiscard]] cbx_command_report box_command(double box_offset_mm, double box_offset_rad, const BoxReading& reading);

 private:
  BrowserSession() = default;
  bool carm_sync();
  session::KeyboardInput keyboard_;
  app::DeviceDrive drive_;
  app::DriveKeys pressed_;  // U, E, Tab since the last tick
  std::vector<std::string> drive_notes_;
  std::unique_ptr<session::Session> session_;
  const LawTapHand* hand_ = nullptr;  // the session's hand (owned by it)
  BrowserBoxLaw box_law_;
  std::vector<float> packed_;
  session::FluoroSwitches switches_;
  BrowserFluoro fluoro_;
  std::unique_ptr<FluoroThread> fluoro_thread_;
  app::CArmPanelModel carm_;
  std::array<double, 9> carm_state_{};
  std::uint64_t record_bytes_ = 0;
};

}  // namespace cathbox::wasm
