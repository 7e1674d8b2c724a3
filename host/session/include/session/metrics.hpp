#pragma once
// The skill metrics of one run, accumulated tick by tick (on the haptic thread, or from a
// replay). Definitions (host/session/README.md, "Metrics"):
//
//   procedure time        from the first tick to the last observed
//   time to target        when the held tool's tip first came within the target radius
//   tip path length       distance travelled by the tip of the tool in the hand, summed over
//                         ticks (taking another tool is not travel)
//   path efficiency       centreline length from the entry to the target ÷ the tip path length
//                         when the target was reached (none before, or without a target)
//   wall contacts         episodes of the tip touching the wall, separated by ≥ 20 ms without
//   peak wall force       largest normal force of any contact of any tool (the session gives
//                         those of converged steps: contact_readings.hpp)
//   time above threshold  time with a contact force above the case's threshold (100 mN default)
//   wrong-branch entries  the tip enters a vessel segment off the centreline route from the
//                         entry to the target, counted once per entry (junctions ignored)
//   retractions           pull-backs of the held tool by ≥ 2 mm from its furthest point since
//                         the last retraction (hysteresis: the next counts after it advances
//                         2 mm from its lowest point)
//   peak insertion speed  largest |Δ insertion| of the held tool over any 50 ms window ÷ 50 ms
//   tool changes          times the trainee took another tool
//   target reached        and the closest approach otherwise
// plus room for the fluoroscopy module: fluoroscopy time, dose-area product, runs, contrast;
// and, in a case with a coil tool and an aneurysm sac, the coiling figures of sim/tool's
// CoilMetrics (coil_metrics.hpp): packing density (coil volume pi/4 d^2 L ÷ sac volume, %),
// coil length deployed, herniations (episodes of coil in the parent artery past the neck
// plane, an error), their extent (the most nodes herniated at once, the deepest past the neck
// plane, mm), microcatheter kick-back (peak, mm) and, per detachment, the pusher's push on its
// coil when it was released (mN; "detached under tension" over tool::CoilMetrics::kNeutral_mN).
// and, per tool (the case's tools, then the coils released), the unconverged share: the ticks
// its step ran out of Newton iterations ÷ the ticks it had a step to solve, in % (a reading of
// the solver, not of the trainee: forces of such steps are not read, contact_readings.hpp).
// and, in a case with a balloon catheter in a meshed vessel, the angioplasty figures of sim/tool
// (angioplasty.hpp): stenosis before and residual stenosis at the lesion (%, 1 - minimal lumen
// diameter ÷ reference diameter), balloon inflations and inflated time, rupture-risk events
// (inflations over 1.1x the reference diameter).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "flow/reperfusion.hpp"
#include "tool/angioplasty.hpp"
#include "tool/coil_metrics.hpp"

namespace cathbox::session {

// A thrombectomy case's figures (the session's ThrombectomyUnit, thrombectomy_unit.hpp): passes,
// eTICI after each (graded from the flow network, Liebeskind et al. JNIS 2019), the first-pass
// effect (eTICI >= 2c after pass 1), emboli (lodged fragments) and those to new territories,
// the time from the start of the run to reperfusion (the end of the first pass reaching
// eTICI >= 2b50), and the balloon guide's flow arrest: its inflations (control 68 accepted) and
// the time with any guide inflated (a guide still inflated counts up to the last tick). The
// angioplasty balloon's inflations are Metrics::balloon_inflations, not these.
// An embolus still travelling when the run ended: where it was, and where it would lodge if
// the flow went on (its transit continued in the network without any arrest, as graded).
struct EmbolusInTransit {
  std::string at;           // the segment it was in
  double at_mm = 0.0;       // along that segment's centreline
  std::string would_lodge;  // the segment it would lodge in ("" if no flow would carry it on)
  bool new_territory = false;  // lodged there, it would starve an outlet outside the target territory
  friend bool operator==(const EmbolusInTransit&, const EmbolusInTransit&) = default;
};

struct ThrombectomyFigures {
  static constexpr std::size_t kMaxPasses = 8;  // passes beyond are counted, not graded one by one
  int passes = 0;
  std::array<flow::Etici, kMaxPasses> etici_after_pass{};
  std::array<double, kMaxPasses> reperfused_pct_after_pass{};
  flow::Etici etici_final = flow::Etici::k0;
  double reperfused_pct_final = 0.0;
  bool first_pass_effect = false;
  int emboli = 0;                // fragments released into the flow: lodged, and at the end those in transit
  int emboli_new_territory = 0;  // of those, the ones starving (or that would starve) a new territory
  std::vector<std::string> emboli_lodged;  // per lodged embolus: the segment it lodged in, in order
  std::vector<EmbolusInTransit> emboli_in_transit;  // set when the run ends (ThrombectomyUnit::finish)
  std::int64_t time_to_reperfusion_us = -1;  // -1: not reperfused
  int balloon_guide_inflations = 0;
  double flow_arrest_s = 0.0;
  int stent_passes = 0;               // of the passes, those made with a stent retriever
  double retrieval_force_peak_N = 0.0;  // the largest pull on a stent's push wire during its passes
  friend bool operator==(const ThrombectomyFigures&, const ThrombectomyFigures&) = default;
};

// One tool's convergence over the run (the session's ContactReadings counts).
struct ToolConvergence {
  std::string tool;                       // its name in the case (a released coil keeps its tool's)
  std::int64_t solved_ticks = 0;          // ticks it had a step to solve (a free node)
  std::int64_t unconverged_ticks = 0;     // of those, ticks the step ran out of iterations
  [[nodiscard]] double unconverged_pct() const {
    return solved_ticks > 0 ? 100.0 * static_cast<double>(unconverged_ticks) / static_cast<double>(solved_ticks) : 0.0;
  }
};

struct Metrics {
  std::int64_t procedure_time_us = 0;
  bool has_target = false;
  bool target_reached = false;
  std::int64_t time_to_target_us = -1;     // -1: not reached
  double closest_to_target_mm = -1.0;      // -1: no target
  double tip_path_mm = 0.0;
  double route_length_mm = -1.0;           // centreline entry -> target; -1: no target
  double path_efficiency = -1.0;           // -1: target not reached
  int wall_contacts = 0;
  double peak_wall_force_mN = 0.0;
  double wall_force_threshold_mN = 100.0;
  std::int64_t time_above_threshold_us = 0;
  int wrong_branch_entries = -1;           // -1: no route (no target)
  int retractions = 0;
  double peak_insertion_speed_mm_s = 0.0;
  int tool_changes = 0;
  double peak_hand_force_mN = 0.0;
  // Per tool, in the snapshot's order; filled by the session each tick.
  std::vector<ToolConvergence> convergence;
  // The largest unconverged share of any tool (0 with none).
  [[nodiscard]] double unconverged_pct_max() const;
  // Filled by the fluoroscopy module; empty (nullopt) until it runs.
  std::optional<double> fluoroscopy_time_s;
  std::optional<double> dose_area_product_mGy_cm2;
  std::optional<int> fluoroscopy_runs;
  std::optional<double> contrast_volume_ml;
  // Filled by the session when the case has a coil tool and an aneurysm sac.
  std::optional<double> packing_density_pct;
  std::optional<double> coil_length_mm;
  std::optional<int> coil_herniations;
  std::optional<int> coil_herniated_peak_nodes;     // the most nodes herniated at once
  std::optional<double> coil_herniated_depth_mm;    // the deepest of them past the neck plane
  std::optional<double> kick_back_mm;
  std::optional<double> kick_forward_mm;  // the tip's climb into the sac, tool::CoilFigures
  // Per detachment (in order), the pusher's push on its coil when it was released (mN, positive
  // pushing the coil on; tool::CoilFigures::detach_force_mN), the largest |force|
  // of them (0 before any) and how many were over tool::CoilMetrics::kNeutral_mN.
  std::vector<double> coil_detach_force_mN;
  std::optional<double> coil_detach_force_peak_mN;
  std::optional<int> coil_detached_under_tension;
  // Released coils at rest are not solved (tool::CoilSleep): coil steps skipped, and times a
  // sleeping coil was woken, since the run began.
  std::optional<std::int64_t> coil_sleep_skipped_steps;
  std::optional<std::int64_t> coil_sleep_wakes;
  // Filled by the session when the case has a balloon catheter in a meshed vessel.
  std::optional<double> stenosis_before_pct;     // with a lesion found in the vessel
  std::optional<double> residual_stenosis_pct;
  std::optional<int> balloon_inflations;
  std::optional<double> balloon_inflated_s;
  std::optional<int> rupture_risk_events;
  // Filled by the session when the case has clots (a thrombectomy case).
  std::optional<ThrombectomyFigures> thrombectomy;
  // A real-time run's haptic ticks dropped (its loop fell behind by more than it catches up:
  // HapticPacer), set when it ends, and read back from its record's end block; none in virtual
  // time. Of the rig, not of the trainee: each dropped tick is a millisecond the wire lagged the hand.
  std::optional<std::int64_t> haptic_dropped_ticks;
  std::int64_t haptic_ticks = 0;  // the ticks the loop ran, beside them
  // The dropped ticks' share of the run's real time (dropped / (ticks + dropped)), in %.
  [[nodiscard]] std::optional<double> haptic_dropped_pct() const;
};

// What the metrics look at in one tick.
struct MetricsTick {
  std::int64_t time_us = 0;
  std::size_t held = 0;                // the tool in the hand
  bool tool_changed = false;           // the trainee took it at this tick
  bool tool_replaced = false;          // a new device on the held tool (a coil loaded at the hub):
                                       // its insertion and tip start afresh, not travel or speed
  double held_insertion_mm = 0.0;      // its commanded insertion
  glm::vec3 tip_mm{0.0F};              // its tip
  std::int32_t tip_segment = -1;       // vessel segment id holding the tip (-1 none, -2 junction)
  bool tip_in_contact = false;
  double tip_force_mN = 0.0;           // largest normal force on those nodes (the held tool's last
                                       // 3), what the "tip on the wall" event reports
  double wall_force_mN = 0.0;          // largest normal force of this tick's contacts (all tools)
  double hand_force_mN = 0.0;          // magnitude of the axial force at the hand
};

struct MetricsSettings {
  std::optional<glm::vec3> target_mm;
  double target_radius_mm = 2.0;
  double route_length_mm = -1.0;             // < 0: none
  std::vector<std::int32_t> route_segments;  // segment ids from the entry to the target
  double wall_force_threshold_mN = 100.0;
  std::int64_t contact_gap_us = 20'000;
  double retraction_mm = 2.0;
  std::int64_t speed_window_us = 50'000;
};

// The metrics as named numbers (booleans 0/1), only those the run has (no target: no time to
// target; no fluoroscopy: none of its figures): what the server indexes and pass criteria name.
struct NamedMetric {
  std::string name;
  double value = 0.0;
};
[[nodiscard]] std::vector<NamedMetric> named_metrics(const Metrics& m);
// Every name named_metrics can give.
[[nodiscard]] std::vector<std::string> metric_names();

class MetricsCollector {
 public:
  explicit MetricsCollector(MetricsSettings settings = {});

  void observe(const MetricsTick& tick);
  // The fluoroscopy unit's figures (session/fluoro_unit.hpp), set after each tick it runs.
  void set_fluoroscopy(double time_s, double dose_area_product_mGy_cm2, int runs, double contrast_volume_ml);
  [[nodiscard]] const Metrics& metrics() const { return m_; }
  // The coiling figures, from the session's tool::CoilMetrics after each tick.
  void set_coiling(const tool::CoilFigures& f);
  // The simulator's coil sleep counts (tool::CoilSleep::skipped_steps, wakes), with the coiling figures.
  void set_coil_sleep(std::int64_t skipped_steps, std::int64_t wakes) {
    m_.coil_sleep_skipped_steps = skipped_steps;
    m_.coil_sleep_wakes = wakes;
  }
  // Tool `t`'s convergence counts (ContactReadings::solved_ticks / held_ticks) after each tick;
  // its name is taken when the tool is first seen (no allocation on later ticks).
  void set_convergence(std::size_t t, std::string_view tool, std::int64_t solved_ticks, std::int64_t unconverged_ticks);
  // The angioplasty figures, from the session's tool::Angioplasty after each tick.
  void set_angioplasty(const tool::AngioplastyFigures& f);
  // A real-time run's dropped haptic ticks and the ticks it ran, when it ends
  // (Metrics::haptic_dropped_ticks).
  void set_haptic_dropped(std::int64_t dropped, std::int64_t ticks) {
    m_.haptic_dropped_ticks = dropped;
    m_.haptic_ticks = ticks;
  }
  // The thrombectomy figures, from the session's ThrombectomyUnit after each tick.
  void set_thrombectomy(const ThrombectomyFigures& f) { m_.thrombectomy = f; }
  // Only the flow-arrest figures (every tick while a guide is inflated: no allocation).
  void set_flow_arrest(int balloon_guide_inflations, double flow_arrest_s) {
    if (!m_.thrombectomy) return;
    m_.thrombectomy->balloon_guide_inflations = balloon_guide_inflations;
    m_.thrombectomy->flow_arrest_s = flow_arrest_s;
  }
  // Events of the last observe(), for the output panel.
  [[nodiscard]] bool contact_began() const { return contact_began_; }
  [[nodiscard]] bool target_just_reached() const { return target_just_reached_; }

  // One line per figure, for stdout and the log.
  [[nodiscard]] static std::string format(const Metrics& m);

 private:
  struct Sample {
    std::int64_t time_us = 0;
    double insertion_mm = 0.0;
  };
  void reset_held(const MetricsTick& tick);
  // The steps of observe(), in order: each updates its own metrics from one tick.
  std::int64_t observe_time(const MetricsTick& t);  // returns the time since the last tick
  void observe_contact(const MetricsTick& t, std::int64_t dt_us);
  void observe_target(const MetricsTick& t);
  void observe_route(const MetricsTick& t);
  void observe_retraction(double insertion_mm);
  void observe_speed(std::int64_t time_us, double insertion_mm);

  MetricsSettings s_;
  Metrics m_;
  bool started_ = false;
  std::int64_t start_us_ = 0;
  std::int64_t last_us_ = 0;
  glm::vec3 last_tip_mm_{0.0F};
  bool in_contact_ = false;
  std::int64_t last_contact_us_ = -1;
  std::int32_t last_segment_ = -1;
  // Retractions of the held tool (hysteresis).
  bool retracting_ = false;
  double extreme_mm_ = 0.0;  // furthest while advancing, lowest while retracting
  // Insertion speed over a window.
  static constexpr std::size_t kSamples = 256;
  std::array<Sample, kSamples> samples_{};
  std::size_t sample_count_ = 0;
  std::size_t sample_head_ = 0;
  bool contact_began_ = false;
  bool target_just_reached_ = false;
};

}  // namespace cathbox::session
