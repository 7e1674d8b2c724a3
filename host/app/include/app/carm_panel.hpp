#pragma once
// The trainer's C-arm panel (Dear ImGui) in the fluoroscopic view, at the top of the right
// column's lower area (the output panel below it): LAO/RAO and cranial/caudal, source-to-image
// distance, table height (the magnification it gives), field of view and collimation, the pulse
// rate, the projections (AP, lateral, obliques, the case's working views), the injection the
// Inject button and the I key give (volume, rate, concentration), roadmap capture and clear,
// and the unit's figures. The fields' logic is CArmPanelModel's; this only draws them and
// returns the controls their edits gave, for the caller to post.
#include <vector>

#include "app/carm_panel_model.hpp"
#include "app/viewport.hpp"
#include "session/control.hpp"
#include "session/fluoro_view.hpp"

namespace cathbox::app {

struct CArmPanelActions {
  std::vector<session::Control> controls;  // in the order the trainee gave them
  bool injection_changed = false;          // the I key's injection: model.injection()
};

// The panel's height at the ImGui default font (the caller reserves it above the output panel).
inline constexpr int kCArmPanelHeight = 300;

// `area`: where to draw (window pixels, origin top left). `driving`: false in Replay mode (the
// fields show the record's C-arm, nothing can be changed).
[[nodiscard]] CArmPanelActions draw_carm_panel(const Viewport& area, CArmPanelModel& model, const session::FluoroView& unit,
                                               bool driving);

}  // namespace cathbox::app
