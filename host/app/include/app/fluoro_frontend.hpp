#pragma once
// Fills FluoroInputs for the trainer's fluoroscopic view from what it has. Today that is the
// session's SceneSnapshot (the tools), without a fluoroscope or contrast in the session:
// continuous fluoroscopy at 15 pulses per second of simulated time in the given pose. This is
// where the session's fluoroscope snapshot (Fluoroscope image, pose, captured scenes: branch
// fluoro-session) plugs in, replacing the assumptions below.
#include "app/fluoro_inputs.hpp"
#include "session/scene_snapshot.hpp"

namespace cathbox::app {

struct SnapshotFluoroSettings {
  flow::CArmPose pose;                 // the C-arm (AP by default)
  double patient_transmission = 0.01;  // HeadPhantom::central_transmission for the pose
  double pulse_rate_hz = 15.0;
  double tip_marker_mm = 30.0;         // every tool's radio-opaque (platinum) distal part
};

[[nodiscard]] FluoroInputs fluoro_inputs_from_snapshot(const session::SceneSnapshot& snapshot,
                                                       const SnapshotFluoroSettings& settings);

}  // namespace cathbox::app
