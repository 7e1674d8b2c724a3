#pragma once
// The keyboard trainee's stent-retriever keys (host/app/README.md, "Keyboard"): U unsheathes,
// E retrieves. Each is a drive of the keyboard hand decided once per frame from the snapshot:
// the tool to select (a select_tool control) and the insertion speed to set on the
// session::KeyboardInput, so the motion is ordinary hand motion (recorded and replayed as any
// key's). Nothing here draws or reads a window (tests/host/app/device_drive_test.cpp).
//
// - U: the stent's carrier (the catheter its push wire runs in, normally the microcatheter) is
//   selected and drawn back at kUnsheathe_mm_s, the push wire held still (the keyboard moves
//   only the held tool), until the whole stent is out of it (ToolView::stent_unsheathed_mm ==
//   stent_length_mm); it stops by itself.
// - E: the stent is selected and pulled back at kRetrieve_mm_s until it is back in a catheter
//   (nothing of it unsheathed), which is where the session ends its pass (a pass running:
//   ToolView::stent_retrieving).
// - A held arrow or WASD key, Tab (or the HUD's switch-tool button), the same key again or the
//   end of the run stops a drive; the other key switches to its drive. A drive also stops when
//   the driven tool is out to its hub (insertion 0).
// - While a box drives the tools (a connected box holds the hand) U and E are refused with a line
//   (the trainee's hands are on the box: they draw the catheter back there), a drive running
//   stops, and the HUD's line says so.
// Shared by cathbox-trainer (once per frame) and the trainee page's haptic worker (host/wasm,
// once per tick: BrowserSession::tick), compiled from this file into both.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "session/scene_snapshot.hpp"

namespace cathbox::app {

struct DriveKeys {
  bool unsheathe = false;  // U pressed this frame
  bool retrieve = false;   // E pressed this frame
  bool cancel = false;     // an arrow / WASD held, or Tab pressed
  bool box = false;        // a connected box holds the hand (not a key: the hand's state this frame)
};

struct DriveCommand {
  bool driving = false;             // set the keyboard's speeds to these (else leave the keys' own)
  double insert_mm_s = 0.0;         // 0 while the wanted tool is not held yet
  std::optional<std::size_t> select;  // post a select_tool control for this tool
  std::string note;                 // a line for the output panel: why a drive stopped or was refused
};

class DeviceDrive {
 public:
  enum class Mode { kIdle, kUnsheathe, kRetrieve };
  static constexpr double kUnsheathe_mm_s = 5.0;
  static constexpr double kRetrieve_mm_s = 10.0;
  static constexpr double kFullyOut_mm = 0.01;  // unsheathed within this of the stent's length

  // Once per frame, with this frame's keys and the snapshot the frame shows.
  [[nodiscard]] DriveCommand update(const DriveKeys& keys, const session::SceneSnapshot& snap);
  [[nodiscard]] Mode mode() const { return mode_; }
  // The HUD's lines for the two keys (empty when the case has no stent retriever in a catheter),
  // e.g. "U: unsheathe the stent (microcatheter back 5 mm/s)", or while a drive runs
  // "U: UNSHEATHING 12 / 20 mm (U, arrows or Tab: stop)"; while a box holds the hand (as of the
  // last update) one line saying the keys are off. `names`: the case's tools.
  [[nodiscard]] std::vector<std::string> hints(const session::SceneSnapshot& snap, const std::vector<std::string>& names) const;

  // The case's first stent retriever that runs in a catheter (-1: none).
  [[nodiscard]] static int stent_tool(const session::SceneSnapshot& snap);

 private:
  [[nodiscard]] DriveCommand box_holds(const DriveKeys& keys);
  [[nodiscard]] DriveCommand start(Mode mode, const session::SceneSnapshot& snap);
  [[nodiscard]] DriveCommand drive(const session::SceneSnapshot& snap);
  [[nodiscard]] DriveCommand stop(std::string note);

  Mode mode_ = Mode::kIdle;
  std::size_t tool_ = 0;  // the tool being driven
  bool pass_seen_ = false;  // a retrieval: the session's pass has been seen running
  bool box_ = false;  // the last update's DriveKeys::box
};

}  // namespace cathbox::app
