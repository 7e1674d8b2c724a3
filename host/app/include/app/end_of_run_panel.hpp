#pragma once
// The end-of-run panel: every metric of the run (session/metrics.hpp), the fluoroscopy figures
// when the case had them, the record's file, and "again" / "replay this run".
#include <string>

#include "app/screen_layout.hpp"
#include "session/metrics.hpp"

namespace cathbox::app {

struct EndOfRunActions {
  bool again = false;
  bool replay = false;
};

// Draws the panel centred on `area` (inside an ImGui frame).
[[nodiscard]] EndOfRunActions draw_end_of_run(const Viewport& area, const session::Metrics& metrics,
                                              const std::string& record_path, bool replaying);

}  // namespace cathbox::app
