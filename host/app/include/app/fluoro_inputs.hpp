#pragma once
// What the fluoroscopic view needs to draw one screen (FluoroRenderer), as plain data a front
// end fills: the C-arm pose, the fluoroscopy unit's FluoroImage (which pulse is shown, held or
// live, subtracted or not, the roadmap), and the image inputs captured at the pulses the image
// is made of: the shown pulse, its run's mask, and the roadmap's peak pulse and its mask. Each
// of those is a FluoroScene: the iodine per contrast cell (in sim/flow ContrastTransport's cell
// order) and the radio-opaque tools at that pulse. No GL.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "base/xxh_hasher.hpp"
#include "flow/c_arm.hpp"
#include "flow/fluoro_dose.hpp"
#include "flow/fluoroscope.hpp"
#include "flow/xray_material.hpp"

namespace cathbox::app {

// A radio-opaque band along a tool, measured back from its distal tip (e.g. a platinum tip
// coil or a marker band): drawn as a cylinder of the tool's radius in `material`.
struct FluoroMarker {
  double from_tip_mm = 0.0;   // distal end of the band, mm proximal of the tip
  double length_mm = 1.0;
  flow::XrayMaterial material = flow::XrayMaterial::kPlatinum;
};

struct FluoroTool {
  std::vector<glm::vec3> nodes_mm;  // proximal to distal
  float radius_mm = 0.18F;
  flow::XrayMaterial material = flow::XrayMaterial::kNitinol;  // the shaft
  std::vector<FluoroMarker> markers;
};

// The image inputs of one pulse.
struct FluoroScene {
  std::int64_t pulse = -1;                 // the Fluoroscope's pulse number; -1: nothing captured
  flow::ExposureMode mode = flow::ExposureMode::kFluoroscopy;  // its dose, hence its noise
  std::vector<float> cell_iodine_mgI_ml;   // per contrast cell; empty: no contrast anywhere
  std::vector<FluoroTool> tools;
};

struct FluoroInputs {
  flow::CArmPose pose;
  flow::FluoroImage image;                 // Fluoroscope::image()
  double patient_transmission = 0.01;      // Fluoroscope::patient_transmission(): the dose control's reference
  flow::DoseSettings dose;
  FluoroScene shown;                       // image.pulse
  FluoroScene mask;                        // image.mask_pulse (when image.subtracted())
  FluoroScene roadmap;                     // image.roadmap_pulse (the peak of a run)
  FluoroScene roadmap_mask;                // that run's mask
};

// The pose's fields into a cache key (what an image depends on: the renderers' caches).
inline void hash_pose(base::XxhHasher& h, const flow::CArmPose& p) {
  h.add(p.lao_deg);
  h.add(p.cranial_deg);
  h.add(p.sid_mm);
  h.add(p.sod_mm);
  h.add(p.table_height_mm);
  h.add(p.isocenter_mm);
  h.add(p.fov_mm);
  h.add(p.collimation);
}

// Empty when the inputs can be drawn for a vessel of `cell_count` contrast cells (0: no vessel,
// whose iodine lists are then not drawn and their size not checked); else one line naming the first bad field, e.g. "FluoroInputs.mask.cell_iodine_mgI_ml: 12
// cells, the vessel has 1309" or "FluoroInputs.shown.tools[0].radius_mm: must be > 0".
[[nodiscard]] std::string check_fluoro_inputs(const FluoroInputs& inputs, std::size_t cell_count);

}  // namespace cathbox::app
