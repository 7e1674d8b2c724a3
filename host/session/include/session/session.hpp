#pragma once
// One run of one case: the simulator, the hand, the haptic tick, the clocks and threads, the
// snapshots for renderers, the event log, the metrics and the recorder. The trainer, `cathbox
// session run|replay|metrics` and the server's checks all run a case through this class.
//
//   auto loaded = session::load_session_case("cases/neuro.case");
//   session::Session s(std::move(loaded.value), std::move(hand));
//   if (!s.record_to("run.cbxrec")) ...         // optional, before the first tick
//   s.step_virtual(1000);                       // virtual time on this thread, or
//   s.start(); ... s.stop();                    // the real-time 1 kHz haptic thread
//
// The tick (haptic thread): the controls posted since the last tick and the hand's own are
// applied; the hand says where the tools are (integers: µm, µrad; clamped to each tool's
// range); the record gets the tick's inputs; the simulator steps; the hand feels the force
// law; metrics, events, observers and the snapshot follow; every `hash_every` ticks the state
// hash goes into the record. Nothing in the tick blocks or allocates once running.
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "session/clock.hpp"
#include "session/contact_readings.hpp"
#include "session/control.hpp"
#include "session/event_log.hpp"
#include "session/fluoro_unit.hpp"
#include "session/hand.hpp"
#include "session/haptic_thread.hpp"
#include "session/metrics.hpp"
#include "session/record_format.hpp"
#include "session/record_header.hpp"
#include "session/recorder.hpp"
#include "session/scene_snapshot.hpp"
#include "session/session_case.hpp"
#include "session/snapshot_exchange.hpp"
#include "session/thrombectomy_unit.hpp"
#include "tool/coil_metrics.hpp"
#include "tool/angioplasty.hpp"
#include "scenario/case_wall.hpp"
#include "tool/simulator.hpp"
#include "tool/snapshot.hpp"

namespace cathbox::session {

struct SessionOptions {
  std::int64_t period_us = 1000;      // the tick (1 kHz)
  std::int64_t hash_every = 100;      // a state hash every this many ticks
  std::int64_t max_ticks = -1;        // the run ends after this many ticks (< 0: no limit)
  bool end_at_target = true;          // the run ends when the tip reaches the target
  std::optional<std::size_t> held_tool;  // the tool in the hand at the start (default: the simulator's)
  std::size_t max_nodes_per_tool = 2048;  // snapshot capacity (nodes beyond are not drawn)
  // The clock start() paces the haptic thread against (null: the machine's monotonic clock; a
  // test gives a VirtualClock, stalls and all).
  device::Clock* real_time_clock = nullptr;
};

// What observers see after each tick (haptic thread; keep it short, no blocking).
struct TickView {
  std::int64_t tick = 0;
  std::int64_t time_us = 0;
  const tool::Simulator& sim;
  const tool::Snapshot& snapshot;
  const TickInput& input;
  std::span<const Control> controls;  // applied at this tick
  const Metrics& metrics;
  const ContactReadings& contacts;  // the wall forces of the converged steps (contact_readings.hpp)
  const ThrombectomyUnit* thrombectomy = nullptr;  // a case with clots: its unit as of this tick
};

class TickObserver {
 public:
  virtual ~TickObserver() = default;
  virtual void observe(const TickView& view) = 0;
};

class Session {
 public:
  Session(std::unique_ptr<SessionCase> scene, std::unique_ptr<Hand> hand, SessionOptions options = {});
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // Before the first tick: record the run (the header from the case and the hand).
  [[nodiscard]] base::Status<> record_to(const std::string& path);
  [[nodiscard]] Recorder* recorder() { return recorder_.get(); }
  // A handler for a control kind (kept by reference; must outlive the session).
  void add_control_handler(std::uint16_t kind, ControlHandler& handler);
  void add_observer(TickObserver& observer);

  // Any thread: a control for the next tick. False when the queue is full or closed (replay).
  bool post(const Control& control) { return controls_.post(control); }
  // The run ends at the next tick (reason: ended by the trainee).
  void end_run() { end_requested_.store(true, std::memory_order_release); }
  // A run paced in real time by a clock outside the session (the trainee page's haptic worker,
  // which steps it in virtual time) tells the ticks its pacer has dropped so far; the run's end
  // keeps the last total as a real-time run keeps its own thread's (Metrics::haptic_dropped_ticks).
  void note_paced_drops(std::int64_t total) { paced_drops_.store(total, std::memory_order_release); }

  // Real time: the haptic thread against the steady clock.
  void start();
  void stop();
  // Virtual time on the calling thread: runs up to `ticks` more ticks; returns how many ran.
  std::int64_t step_virtual(std::int64_t ticks);

  // Any thread.
  [[nodiscard]] bool over() const { return over_.load(std::memory_order_acquire); }
  [[nodiscard]] std::int64_t ticks() const { return ticks_.load(std::memory_order_acquire); }
  [[nodiscard]] std::size_t held_tool() const { return held_.load(std::memory_order_relaxed); }
  [[nodiscard]] double haptic_rate_hz() const;
  [[nodiscard]] std::int64_t dropped_ticks() const;
  [[nodiscard]] std::int64_t haptic_cpu_time_us() const;
  [[nodiscard]] std::string haptic_scheduling() const;
  [[nodiscard]] SnapshotExchange<SceneSnapshot>& snapshots() { return exchange_; }
  [[nodiscard]] EventLog& events() { return events_; }

  // Fixed for the life of the session.
  [[nodiscard]] const SessionCase& scene() const { return *scene_; }
  [[nodiscard]] const std::vector<std::string>& tool_names() const { return tool_names_; }
  [[nodiscard]] const std::string& hand_description() const { return hand_description_; }
  [[nodiscard]] HandKind hand_kind() const { return hand_->kind(); }
  [[nodiscard]] const SessionOptions& options() const { return options_; }
  // The contrast cells a renderer draws SceneSnapshot::fluoro's iodine on (empty without a
  // vessel network).
  [[nodiscard]] const std::vector<FluoroCell>& fluoro_cells() const;
  // Any thread: the vessel wall the simulation uses now, when a balloon has widened it
  // (SceneSnapshot::wall_generation > 0): the widened model and its surface mesh. Empty while
  // the case's own surface (scene().mesh()) is the wall, and in cases without a balloon.
  [[nodiscard]] std::shared_ptr<const tool::WallSurface> wall_surface() const;
  // The compliant wall the pulse moves (a case's `wall` line on a vessel; null otherwise): its
  // segments' distension, immutable, for renderers that move the drawn surface by
  // SceneSnapshot::wall_pressure_kPa.
  [[nodiscard]] const tool::CaseWallField* wall_field() const { return wall_field_.get(); }
  // The header a record of this session gets.
  [[nodiscard]] RecordHeader record_header() const;

  // Once the run is over or the threads are stopped (not while a tick may run).
  [[nodiscard]] const Metrics& metrics() const { return metrics_.metrics(); }
  [[nodiscard]] Hand& hand() { return *hand_; }
  [[nodiscard]] const tool::Simulator& simulator() const { return *sim_; }
  // A diagnostic hook on the simulator's solves (tool::Simulator::set_solve_observer), set
  // before the run starts; for benches.
  void set_solve_observer(tool::Simulator::SolveObserver* observer) { sim_->set_solve_observer(observer); }
  [[nodiscard]] record::EndReason end_reason() const { return end_reason_; }
  // The fluoroscopy unit (null without a vessel network).
  [[nodiscard]] const FluoroUnit* fluoro() const { return fluoro_.get(); }
  // The thrombectomy unit (null without clots in a vessel network).
  [[nodiscard]] const ThrombectomyUnit* thrombectomy() const { return thrombectomy_.get(); }
  [[nodiscard]] const std::string& end_text() const { return end_text_; }

 private:
  class Sink;
  class SelectTool;
  class DetachCoil;
  class LoadCoil;
  class BalloonControl;
  // The parts the constructor builds, in order.
  void build_simulator();
  void add_flow_units();
  void add_device_units();
  // The tools' unconverged shares into the metrics (ContactReadings' counts).
  void observe_convergence();
  bool tick();
  // In the haptic loop's wait after a tick: the next step's work that can be done ahead
  // (Simulator::prepare_next_step; the results are the same either way).
  void prepare_next_tick();
  // The steps of a tick, in order (session.cpp numbers them).
  bool ends_before(std::int64_t n);  // the time limit or the trainee's end: the run ended
  void read_hand(std::int64_t n);
  void step_world(std::int64_t n);
  void pulse_wall();  // the compliant wall's pressure for the tick being stepped
  HandFeedback feel(std::int64_t n);
  void observe(std::int64_t n, const HandFeedback& fb);
  void log_events(int tip_segment, double tip_force_mN);
  void log_partings();
  void apply(Control control);
  void end(record::EndReason reason, std::string text);
  // The snapshot: what is fixed for the run into every slot once (before the first tick), then
  // the tick's state into the writer's slot after each tick.
  void prepare_snapshot(SceneSnapshot& s) const;
  void publish();
  void publish_clots(SceneSnapshot& s) const;  // publish(): a thrombectomy case's part
  [[nodiscard]] const HapticThread* active_thread() const;
  // A run paced in real time: the ticks dropped so far (its own thread's, or what its outside
  // pacer told); none in virtual time.
  [[nodiscard]] std::optional<std::int64_t> real_time_drops() const;
  [[nodiscard]] std::int64_t clock_now_us();
  [[nodiscard]] device::Clock& real_clock();  // what start() paces against (SessionOptions::real_time_clock)
  void log(const char* fmt, ...) __attribute__((format(printf, 2, 3)));
  // A coil control the simulator refused is logged ("VERB refused: why"), not applied, not
  // recorded: false. True when it was done.
  bool device_done(tool::DeviceError e, const char* verb);
  // The hand's clamp for tool t from the simulator (at case load and after a coil load).
  void update_max_insertion(std::size_t t);

  std::unique_ptr<SessionCase> scene_;
  std::unique_ptr<Hand> hand_;
  SessionOptions options_;
  std::string hand_description_;
  std::vector<std::string> tool_names_;
  // A balloon catheter in a meshed vessel: the lumen it widens and the walls swapped into sim_
  // (synchronous builds in virtual time, a worker thread in real time; sim/tool/README.md).
  // Declared before sim_, which uses its wall.
  std::unique_ptr<tool::Angioplasty> angioplasty_;
  // A case's compliant wall on a vessel (no balloon): the world's wall moved by the pulse, and the
  // pulse's pressure amplitude over the mean (the inlet's pressure above venous, kPa).
  std::unique_ptr<tool::CaseWallField> wall_field_;
  double pulse_mean_kPa_ = 0.0;
  std::unique_ptr<tool::Simulator> sim_;
  tool::Snapshot snap_;
  TickInput input_;
  std::int64_t tick_ = 0;  // the next tick
  std::atomic<std::int64_t> ticks_{0};
  std::atomic<std::size_t> held_{0};
  MetricsCollector metrics_;
  ContactReadings contacts_{0};  // the wall forces the metrics and events read (converged steps)
  SnapshotExchange<SceneSnapshot> exchange_;
  EventLog events_;
  ControlQueue controls_;
  std::array<ControlHandler*, 128> handlers_{};
  std::unique_ptr<SelectTool> select_tool_;
  bool every_law_ = false;  // the hand feels every tool's law (a box per tool), not only the held one's
  std::unique_ptr<FluoroUnit> fluoro_;
  std::unique_ptr<ThrombectomyUnit> thrombectomy_;  // a case with clots (thrombectomy_unit.hpp)
  std::uint64_t flow_generation_ = 0;  // the thrombectomy unit's solves the fluoroscopy has taken
  std::uint64_t figures_generation_ = 0;  // the thrombectomy unit's solves the metrics have taken
  std::unique_ptr<DetachCoil> detach_coil_;
  std::unique_ptr<LoadCoil> load_coil_;
  std::optional<tool::CoilMetrics> coil_metrics_;  // a case with a coil tool and an aneurysm sac
  std::unique_ptr<BalloonControl> balloon_control_;
  std::unique_ptr<Sink> sink_;
  std::array<Control, 64> applied_{};
  std::size_t applied_count_ = 0;
  bool tool_changed_ = false;
  bool coil_loaded_ = false;  // a load_coil applied at this tick (metrics: the held tool replaced)
  std::array<bool, kMaxTools> parting_{};  // per tool: its coil's detachment zone parted last tick
  int rupture_events_ = 0;  // rupture-risk events logged so far
  std::vector<TickObserver*> observers_;
  std::unique_ptr<Recorder> recorder_;
  device::SystemClock steady_;
  VirtualClock virtual_clock_;
  std::unique_ptr<HapticThread> real_thread_;
  std::unique_ptr<HapticThread> virtual_thread_;
  std::atomic<bool> over_{false};
  std::atomic<bool> end_requested_{false};
  std::atomic<std::int64_t> paced_drops_{-1};  // note_paced_drops' total; -1: never told
  record::EndReason end_reason_ = record::EndReason::kStopped;
  std::string end_text_;
  BoxStatus last_box_{};
};

}  // namespace cathbox::session
