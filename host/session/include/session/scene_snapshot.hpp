#pragma once
// What a renderer needs from one haptic tick, copied by the haptic thread into a slot of
// a SnapshotExchange. The vectors are reserved up front so publishing does not allocate.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "session/fluoro_view.hpp"
#include "session/hand.hpp"
#include "session/metrics.hpp"

namespace cathbox::session {

struct ToolView {
  std::vector<glm::vec3> nodes_mm;  // proximal (entry) to distal (tip)
  std::vector<glm::vec3> frames;    // one normal direction per node (may be empty)
  float radius_mm = 0.2F;
  bool active = false;              // the tool in the trainee's hand
  float stent_length_mm = 0.0F;     // a push wire's stent retriever over its distal end (0: none)
  // A stent tool's push wire's own radius (the tool's narrowest node as built, before its stent
  // expands); radius_mm is then its widest, the expanded stent's. Drawn so in the fluoroscopy:
  // the wire thin, the stent section expanded. This and stent_length_mm are fixed for the run:
  // written once into every slot before the first tick.
  float wire_radius_mm = 0.0F;
  // A stent tool (the trainer's U and E keys, host/app/device_drive.hpp): the catheter its push
  // wire runs in (fixed for the run; -1: none or in the vessel), how much of the stent is out of
  // every catheter (tool::StentState::unsheathed_mm), whether its retrieval pass is running.
  int stent_carrier = -1;
  float stent_unsheathed_mm = 0.0F;
  bool stent_retrieving = false;
};

// A clot of the case (or an embolus a pass left), as the 3D views draw it: a body of its radius
// from its proximal face to its distal end. Removed clots are no longer listed. After them, the
// fragments still travelling with the flow (kInTransit): their length along the centreline of
// the segment they are in, up to their leading point (not drawn in the fluoroscopy: a clot is not
// radio-opaque; host/session/README.md, "Thrombectomy").
enum class ClotState : std::uint8_t {
  kInPlace,  // where the case (or the flow, for an embolus) put it
  kEngaged,  // a stent retriever expanded across it, or an aspiration catheter on its face
  kDragged,  // held by a stent retriever being withdrawn: it moves with the stent
  kInTransit,  // a fragment carried by the flow, not lodged yet
};

struct ClotView {
  static constexpr int kAxisPoints = 9;
  glm::vec3 start_mm{0.0F};  // proximal face
  glm::vec3 end_mm{0.0F};    // distal end
  // Its axis from face to end (start_mm and end_mm its first and last points): along the vessel's
  // centreline in place, along the stent's path while a stent drags it.
  std::array<glm::vec3, kAxisPoints> axis_mm{};
  float radius_mm = 0.0F;
  ClotState state = ClotState::kInPlace;
};

struct ContactView {
  glm::vec3 point_mm{0.0F};
  float force_mN = 0.0F;
};

struct SceneSnapshot {
  static constexpr int kMaxTools = static_cast<int>(session::kMaxTools);
  static constexpr int kMaxCoils = static_cast<int>(session::kMaxReleasedCoils);
  static constexpr std::size_t kMaxContacts = 64;
  static constexpr int kMaxClots = 16;

  std::int64_t sim_time_us = 0;
  std::int64_t tick = 0;              // ticks run so far
  std::size_t held_tool = 0;
  bool held_coil_attached = false;  // the held tool's coil is not released yet (detach_coil would)
  bool held_coil_parting = false;   // ... and its detachment zone is parting (released within 0.1 s)
  bool held_next_coil = false;      // its coil is released and the case lists a next (load_coil would)
  std::array<ToolView, kMaxTools> tools;
  int tool_count = 0;                 // the case's tools (the simulator's, in case order)
  // The coils released so far (sim::tool's Snapshot lists them after the tools), in the order
  // they were detached: platinum, drawn in the 3D view and in the fluoroscopy.
  std::array<ToolView, kMaxCoils> coils;
  int coil_count = 0;
  glm::vec3 tip_mm{0.0F};
  glm::vec3 tip_direction{1.0F, 0.0F, 0.0F};
  glm::vec3 tip_up{0.0F, 0.0F, 1.0F};
  std::vector<ContactView> contacts;

  double insertion_mm = 0.0;
  double rotation_rad = 0.0;
  double hand_force_mN = 0.0;
  double hand_torque_mNmm = 0.0;
  // The largest wall force of this tick as the metrics read it (converged steps only,
  // contact_readings.hpp); `contacts` carry the simulator's forces as they are.
  double wall_force_mN = 0.0;
  double haptic_rate_hz = 0.0;
  std::int64_t haptic_ticks = 0;
  std::int64_t dropped_ticks = 0;
  Metrics metrics;
  bool run_over = false;  // target reached, the hand finished, or the run was ended
  // The vessel walls swapped in so far (a balloon widened the lumen; 0: the case's surface).
  // When it changes, Session::wall_surface() has the new lumen's model and mesh to draw.
  std::uint64_t wall_generation = 0;
  // A compliant wall's transmural pressure over the mean (kPa; 0 without one or without a
  // pulse): Session::wall_field()'s distension at it is how far the wall has moved.
  double wall_pressure_kPa = 0.0;
  // Thrombectomy (thrombectomy_unit.hpp): the index of the case's first aspiration catheter and
  // of its first catheter with a balloon (-1: none), whether each is on / inflated now.
  int aspiration_tool = -1;
  bool aspirating = false;
  int balloon_guide_tool = -1;
  bool flow_arrest = false;
  // The clots that remain (thrombectomy_unit.hpp: the case's, and the emboli of the passes).
  std::array<ClotView, kMaxClots> clots;
  int clot_count = 0;     // the clots that remain, then the fragments in transit (up to kMaxClots)
  int clots_removed = 0;  // taken out by the passes so far
  FluoroView fluoro;      // the fluoroscopy unit (fluoro.available: the case has a vessel network)

  // Lets the vectors hold `nodes_per_tool` nodes per tool and per coil without allocating.
  void reserve(std::size_t nodes_per_tool) {
    for (ToolView& t : tools) {
      t.nodes_mm.reserve(nodes_per_tool);
      t.frames.reserve(nodes_per_tool);
    }
    for (ToolView& c : coils) {
      c.nodes_mm.reserve(nodes_per_tool);
      c.frames.reserve(nodes_per_tool);
    }
    contacts.reserve(kMaxContacts);
  }
};

}  // namespace cathbox::session
