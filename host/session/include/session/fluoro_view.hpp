#pragma once
// What a fluoroscopy renderer needs, published with every SceneSnapshot (SceneSnapshot::fluoro):
// the C-arm pose, the fluoroscopy unit's image state (flow::FluoroImage: the pulse shown, beam
// on / last-image hold, run and mask, roadmap), and the image's inputs captured at its pulses
// (iodine per contrast cell at the shown pulse, its mask, the roadmap pulse and the roadmap's
// mask; the tools' nodes at the shown pulse). A renderer maps it to "C-arm pose + FluoroImage +
// per-cell iodine + tool nodes": the cells are Session::fluoro_cells() (fixed for the session),
// in the same order as every iodine vector here.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "flow/c_arm.hpp"
#include "flow/fluoroscope.hpp"
#include "session/hand.hpp"

namespace cathbox::session {

// One contrast transport cell: a piece of a vessel segment's centreline.
struct FluoroCell {
  std::uint32_t segment = 0;    // index into the vessel model's segments
  float arc_begin_mm = 0.0F;    // along the segment's centreline from its first point
  float arc_end_mm = 0.0F;
  glm::vec3 centre_mm{0.0F};    // the centreline point halfway
  float radius_mm = 0.0F;       // the lumen radius there
};

struct FluoroView {
  bool available = false;             // the case has a vessel network (else nothing below is set)
  flow::CArmPose pose;                // the C-arm now
  flow::FluoroImage image;            // the pulse on screen, hold, run, mask and roadmap pulses
  double pulse_rate_hz = 15.0;
  bool injecting = false;             // contrast is flowing from the catheter now
  flow::FluoroMetrics exposure;       // fluoroscopy time, DAP (Gy cm^2), runs, pulses
  double contrast_ml = 0.0;           // injected so far
  // Bumped whenever the vectors below change (a pulse, a roadmap capture or clear): a renderer
  // re-uploads them only then.
  std::int64_t inputs_version = 0;
  // mgI/mL per cell of Session::fluoro_cells(). Empty when there is no such image: before the
  // first pulse; no mask unless the shown pulse belongs to a run; no roadmap unless captured.
  std::vector<float> iodine_mgI_ml;               // at image.pulse
  std::vector<float> mask_iodine_mgI_ml;          // at image.mask_pulse
  std::vector<float> roadmap_iodine_mgI_ml;       // at image.roadmap_pulse (the run's peak)
  std::vector<float> roadmap_mask_iodine_mgI_ml;  // at that run's mask
  // The tools as they were at image.pulse, proximal to distal (the live ones are SceneSnapshot::tools).
  std::array<std::vector<glm::vec3>, kMaxTools> pulse_tool_nodes_mm;
  int pulse_tool_count = 0;
  // The released coils at image.pulse (the live ones are SceneSnapshot::coils).
  std::array<std::vector<glm::vec3>, kMaxReleasedCoils> pulse_coil_nodes_mm;
  int pulse_coil_count = 0;

  // Capacity so that publishing never allocates.
  void reserve(std::size_t cells, std::size_t nodes_per_tool) {
    iodine_mgI_ml.reserve(cells);
    mask_iodine_mgI_ml.reserve(cells);
    roadmap_iodine_mgI_ml.reserve(cells);
    roadmap_mask_iodine_mgI_ml.reserve(cells);
    for (std::vector<glm::vec3>& t : pulse_tool_nodes_mm) t.reserve(nodes_per_tool);
    for (std::vector<glm::vec3>& c : pulse_coil_nodes_mm) c.reserve(nodes_per_tool);
  }
};

}  // namespace cathbox::session
