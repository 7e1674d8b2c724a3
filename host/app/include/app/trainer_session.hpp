#pragma once
// One training run on one case: the vessel surface, the tools and their simulation, the box
// (or the keyboard, or the scripted hand), the haptic thread and its hand-off to the renderer.
// The haptic side fills SceneSnapshots; the render side only reads them.
#include <memory>
#include <optional>
#include <string>

#include <glm/vec3.hpp>

#include "app/event_log.hpp"
#include "app/keyboard_hand.hpp"
#include "app/scene_snapshot.hpp"
#include "app/snapshot_exchange.hpp"
#include "app/trainer_options.hpp"
#include "vessel/surface_mesh.hpp"

namespace cathbox::app {

enum class HandSource {
  kBox,       // the box through BoxClient (real or emulated)
  kKeyboard,  // keyboard and mouse
  kScripted,  // the scripted hand (headless runs)
};

struct SessionConfig {
  std::string case_path;
  BoxChoice box = BoxChoice::kAuto;
  std::string emu_socket;
  bool scripted_hand = false;   // headless: no box, no keyboard
  std::string emu_program;      // path of cathbox-emu (for BoxChoice::kAuto / kEmulator)
};

class TrainerSession {
 public:
  virtual ~TrainerSession() = default;

  // Loads the case and connects the hand; on failure returns null with one line in `error`.
  [[nodiscard]] static std::unique_ptr<TrainerSession> open(const SessionConfig& config,
                                                            std::string& error);

  // The surface the simulation uses (drawn in the local view) and, for large surfaces, a
  // coarser subdivision level of the same vessels for the global view (else empty).
  [[nodiscard]] virtual const vessel::SurfaceMesh& vessel_mesh() const = 0;
  [[nodiscard]] virtual const vessel::SurfaceMesh& overview_mesh() const = 0;
  [[nodiscard]] virtual std::optional<glm::vec3> target_mm() const = 0;
  [[nodiscard]] virtual float target_radius_mm() const = 0;
  [[nodiscard]] virtual std::string case_name() const = 0;
  [[nodiscard]] virtual std::string vessel_file() const = 0;  // the HCLM file of the case
  [[nodiscard]] virtual std::string device_status() const = 0;
  [[nodiscard]] virtual std::string active_tool_name() const = 0;
  [[nodiscard]] virtual HandSource hand() const = 0;
  // The first point of the vessel wall along a ray (the collision tree's ray cast), for
  // picking in the global view; safe from the render thread.
  [[nodiscard]] virtual std::optional<glm::vec3> pick(const glm::vec3& origin_mm, const glm::vec3& direction) const = 0;

  // Real time: the haptic thread at 1 kHz against the steady clock.
  virtual void start() = 0;
  virtual void stop() = 0;
  // Virtual time, on the calling thread: runs `ticks` more haptic ticks (deterministic).
  virtual void step_virtual(std::int64_t ticks) = 0;
  // The run is over (target reached, scripted hand done, or ended by the trainee).
  [[nodiscard]] virtual bool over() const = 0;
  virtual void end_run() = 0;
  [[nodiscard]] virtual double haptic_rate_hz() const = 0;
  [[nodiscard]] virtual std::int64_t haptic_ticks() const = 0;
  [[nodiscard]] virtual std::int64_t haptic_cpu_time_us() const = 0;
  // How the real-time haptic thread is scheduled ("real-time (SCHED_FIFO)", "normal", ...).
  [[nodiscard]] virtual std::string haptic_scheduling() const = 0;

  [[nodiscard]] virtual KeyboardHand& keyboard() = 0;
  [[nodiscard]] virtual SnapshotExchange<SceneSnapshot>& snapshots() = 0;
  [[nodiscard]] virtual EventLog& events() = 0;
  [[nodiscard]] virtual RunSummary summary() const = 0;
};

}  // namespace cathbox::app
