#pragma once
// The fluoroscopy unit inside a session: a flow::Fluoroscope (pedal, pulses, runs, roadmap,
// dose) and a flow::ContrastTransport over the case's blood flow, driven by the session's
// ticks in virtual time, and the handler of the fluoroscopy controls (kinds 32..37,
// fluoro_controls.hpp). Every case with a vessel network has one (SessionCase::flow).
//
// - Time: tick(now_us) after the simulator's step; the transport steps at its own fixed
//   10 ms (100 Hz) whenever a whole step fits before now (resting, with steady flow, until the
//   first injection), on the haptic thread: a step of the
//   neuro graph costs ~25 µs median, ~37 µs p99 (sim/flow/README.md), within the 1 ms tick
//   (bench_session measures the tick with contrast flowing). Deterministic: a replay applying
//   the same controls at the same ticks reproduces every number.
// - Injection (kInject) starts at the tip of the catheter the contrast goes through: the held
//   tool when it is a catheter, else the catheter it runs in, else the case's first catheter;
//   the tip's segment is found with flow::CenterlineLocator. Refused (logged, not recorded)
//   without a catheter or when the tip is outside the lumen or in no flow.
// - At each pulse the image inputs are captured (iodine per cell, the tools' nodes), the run's
//   mask kept, the iodine in the collimated field reported for the peak (flow::FieldIodine),
//   and the peak's inputs kept for a roadmap.
// - Nothing allocates after construction (buffers sized for the cells and the tools' nodes).
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "flow/contrast_transport.hpp"
#include "flow/fluoroscope.hpp"
#include "session/control.hpp"
#include "session/fluoro_controls.hpp"
#include "session/fluoro_view.hpp"
#include "session/metrics.hpp"
#include "tool/snapshot.hpp"
#include "tool/tool_spec.hpp"

namespace cathbox::session {

class FluoroUnit final : public ControlHandler {
 public:
  // `network` and `snapshot` (the session's last tick) must outlive the unit.
  // `pose`: the C-arm at the start (the case's first working projection, isocentre on its target).
  FluoroUnit(const flow::FlowNetwork& network, const std::vector<tool::ToolSpec>& tools,
             const tool::Snapshot& snapshot, std::size_t max_nodes_per_tool, const flow::CArmPose& pose = {});

  // The control kinds this unit handles (register each with the session).
  static constexpr std::array<ControlKind, 6> kKinds{ControlKind::kFluoroPedal,  ControlKind::kInject,
                                                    ControlKind::kCArmAngles,   ControlKind::kCArmGeometry,
                                                    ControlKind::kPulseRate,    ControlKind::kRoadmap};
  bool apply(Control& control, ControlContext& context) override;

  // Advances the transport and the fluoroscope to now_us (non-decreasing): the end of the
  // tick whose step produced the snapshot given at construction.
  void tick(std::int64_t now_us);
  // The network was solved again (a thrombectomy pass, a balloon guide): the contrast follows
  // the new flows from the next transport step.
  void flows_changed() { transport_.refresh_flows(); }

  // A control has been applied (the state hash covers the unit from then on, so records of runs
  // that never used it keep their hashes).
  [[nodiscard]] bool used() const { return used_; }
  // XXH3-64 of `seed` and the unit's state (concentrations, image, exposure, pose, injection).
  [[nodiscard]] std::uint64_t hash(std::uint64_t seed) const;
  // Fills the metrics' fluoroscopy figures.
  void fill(MetricsCollector& metrics) const;
  // Copies the renderer's view into a snapshot slot (no allocation once reserved).
  void publish(FluoroView& view) const;

  [[nodiscard]] const flow::Fluoroscope& fluoroscope() const { return scope_; }
  [[nodiscard]] const flow::ContrastTransport& transport() const { return transport_; }
  [[nodiscard]] const std::vector<FluoroCell>& cells() const { return cells_; }

 private:
  bool inject(const fluoro_control::InjectPayload& injection, ControlContext& ctx);
  bool move_carm(const flow::CArmPose& pose, ControlContext& ctx);
  void capture_pulse(const flow::FluoroTick& t);
  void log(ControlContext& ctx, const char* fmt, ...) __attribute__((format(printf, 3, 4)));

  const flow::FlowNetwork& network_;
  std::vector<tool::ToolSpec> tools_;
  const tool::Snapshot& snap_;
  flow::ContrastTransport transport_;
  flow::Fluoroscope scope_;
  flow::FieldIodine field_;
  std::vector<FluoroCell> cells_;
  std::int64_t transport_step_us_ = 10'000;
  std::int64_t transport_steps_ = 0;
  bool used_ = false;
  // Image inputs, mgI/mL per cell.
  std::vector<float> shown_, previous_, run_mask_, peak_, peak_mask_, roadmap_, roadmap_mask_;
  bool have_shown_ = false;
  std::array<std::vector<glm::vec3>, kMaxTools> pulse_nodes_;
  int pulse_tool_count_ = 0;
  std::array<std::vector<glm::vec3>, kMaxReleasedCoils> pulse_coil_nodes_;  // released coils
  int pulse_coil_count_ = 0;
  std::int64_t inputs_version_ = 0;
};

}  // namespace cathbox::session
