#pragma once
// Replay mode's controls, along the bottom of the global view: play / pause, speed, a seek bar
// over the record's length, where the play head is, the state-hash check so far, the records
// in the records folder to open another, and back to a live run.
#include <cstdint>
#include <string>
#include <vector>

#include "app/screen_layout.hpp"
#include "session/replay_player.hpp"

namespace cathbox::app {

struct ReplayPanelActions {
  std::string open;        // a record to open instead
  bool back_to_live = false;
};

class ReplayPanel {
 public:
  // The records folder listed for "open" (most recent first, re-read on demand).
  explicit ReplayPanel(std::string records_dir) : records_dir_(std::move(records_dir)) {}
  // Draws the controls and applies play / pause / speed / seek to `player`.
  [[nodiscard]] ReplayPanelActions draw(const Viewport& global, session::ReplayPlayer& player);

 private:
  void rescan();
  static void draw_transport(session::ReplayPlayer& player, float width);
  static void draw_checks(session::ReplayPlayer& player);
  void draw_records(session::ReplayPlayer& player, float width, ReplayPanelActions& act);

  std::string records_dir_;
  std::vector<std::string> records_;
  bool scanned_ = false;
};

}  // namespace cathbox::app
