#pragma once
// Fills FluoroInputs for the trainer's fluoroscopic view from the session's SceneSnapshot. With
// the session's fluoroscopy unit (SceneSnapshot::fluoro, every case with a vessel network): its
// C-arm pose, FluoroImage (pulse shown, hold, run and mask, roadmap) and the per-cell iodine it
// captured at those pulses, the tools and the released coils (platinum, SceneSnapshot::coils) as
// they were at the shown pulse (mask and roadmap scenes
// carry no tools: subtraction removes what did not move). Without it (analytic tubes):
// continuous fluoroscopy at the settings' pulse rate in the settings' pose, no contrast.
#include "app/fluoro_inputs.hpp"
#include "session/scene_snapshot.hpp"

namespace cathbox::app {

struct SnapshotFluoroSettings {
  flow::CArmPose pose;                 // the C-arm (AP by default) when the session has no unit
  double patient_transmission = 0.01;  // HeadPhantom::central_transmission for the pose
  double pulse_rate_hz = 15.0;
  double tip_marker_mm = 30.0;         // every tool's radio-opaque (platinum) distal part
};

// A stent retriever's push wire (ToolView::stent_length_mm > 0) shows no platinum tip but the
// stent's platinum markers, as on the devices (Solitaire-type: one proximal, three distal; the
// nitinol struts barely show). Crimped in its catheter: a band this long at each end of the
// stent; expanded: a marker this long on the axis at its proximal end and kStentDistalMarkers
// at the struts' distal ends round its expanded radius, each kStentMarkerRadius_mm thick (an
// estimate for ~0.3 mm marker coils), the struts themselves not drawn.
inline constexpr double kStentMarker_mm = 1.0;
inline constexpr double kStentMarkerRadius_mm = 0.15;
inline constexpr int kStentDistalMarkers = 3;

[[nodiscard]] FluoroInputs fluoro_inputs_from_snapshot(const session::SceneSnapshot& snapshot,
                                                       const SnapshotFluoroSettings& settings);

}  // namespace cathbox::app
