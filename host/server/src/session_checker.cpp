// The record checker over host/session: a record is accepted only if it replays exactly (every
// state hash matches) on the case it carries; its metrics are what the replay measured, not
// anything the uploader claims.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string_view>
#include <utility>

#include <nlohmann/json.hpp>

#include "flow/reperfusion.hpp"
#include "record_scan.hpp"
#include "server/server_app.hpp"
#include "server/upload_limits.hpp"
#include "session/record_reader.hpp"
#include "session/replay.hpp"
#include "scenario/case_file.hpp"

namespace cathbox::server {
namespace {

constexpr std::int64_t kTracePeriod_us = 50'000;  // one sample every 50 ms of the run
constexpr std::size_t kMaxTraceSamples = 9'000;  // longer runs: every k-th sample (wall force: the peak of the k)
constexpr std::size_t kTraceNodes = 24;          // the held tool's shape: at most this many nodes, the tip always
constexpr std::size_t kMaxTraceEvents = 5'000;

// To 0.01 (mm, mN, degrees): a trace is drawn, not replayed.
double r2(double v) { return std::round(v * 100.0) / 100.0; }

// Samples every tick the replay runs: the held tool and forces (in a thrombectomy case the pull
// the session reads as retrieval force); and events, from the metrics' counters (a wall contact
// starting, a wrong-branch entry, the target reached, a thrombectomy pass, an embolus) and from the
// controls the session accepted (an injection, a balloon guide inflated: a flow arrest).
class TraceObserver final : public session::TickObserver {
 public:
  struct Sample {
    std::int64_t t_us = 0;
    glm::dvec3 tip{0.0};
    double insertion_mm = 0.0;
    double rotation_deg = 0.0;
    double hand_mN = 0.0;
    double wall_peak_mN = 0.0;
    double retrieval_mN = 0.0;  // the peak pull on a stent being retrieved since the last sample
    bool fluoro = false;
    std::vector<double> nodes;  // x, y, z of up to kTraceNodes nodes (to 0.01 mm: short in JSON)
  };
  struct Event {
    std::int64_t t_us = 0;
    const char* kind = "";
    int index = 0;  // a pass's or an embolus's number (1-based), 0 for the other kinds
  };

  void observe(const session::TickView& v) override {
    // The wall forces the metrics read: those of the converged steps (session/contact_readings.hpp).
    interval_wall_ = std::max(interval_wall_, v.contacts.wall_mN());
    if (v.thrombectomy != nullptr) interval_retrieval_ = std::max(interval_retrieval_, v.thrombectomy->retrieval_pull_mN());
    const session::Metrics& m = v.metrics;
    if (started_) {
      thrombectomy_events(v.time_us, m);
      if (m.wall_contacts > last_.wall_contacts) event(v.time_us, "wall_contact");
      if (m.wrong_branch_entries > last_.wrong_branch_entries) event(v.time_us, "wrong_branch");
      if (m.target_reached && !last_.target_reached) event(v.time_us, "target_reached");
      if (m.tool_changes > last_.tool_changes) event(v.time_us, "tool_change");
      if (m.fluoroscopy_runs.value_or(0) > last_.fluoroscopy_runs.value_or(0)) event(v.time_us, "fluoroscopy");
      // An injection, a flow arrest: the controls the session accepted at this tick (the contrast
      // volume grows per 10 ms transport step, not per tick: no edge of it is one injection).
      for (const session::Control& c : v.controls) {
        if (c.kind == static_cast<std::uint16_t>(session::ControlKind::kInject)) event(v.time_us, "injection");
        if (c.kind == static_cast<std::uint16_t>(session::ControlKind::kBalloonGuide) && c.size == 2 && c.payload[1] == 1) {
          event(v.time_us, "flow_arrest");
        }
      }
      fluoro_ = m.fluoroscopy_time_s.value_or(0.0) > last_.fluoroscopy_time_s.value_or(0.0);
    }
    if (!started_) {
      for (const tool::ToolSnapshot& t : v.snapshot.tools) tools_.push_back(t.name);
    }
    started_ = true;
    last_ = m;
    if (!samples_.empty() && v.time_us - samples_.back().t_us < kTracePeriod_us) return;
    Sample s;
    s.t_us = v.time_us;
    s.wall_peak_mN = interval_wall_;
    s.retrieval_mN = interval_retrieval_;
    s.fluoro = fluoro_;
    interval_wall_ = 0.0;
    interval_retrieval_ = 0.0;
    if (v.snapshot.active_tool < v.snapshot.tools.size()) {
      const tool::ToolSnapshot& t = v.snapshot.tools[v.snapshot.active_tool];
      s.tip = t.tip.position_mm;
      s.insertion_mm = t.insertion_mm;
      s.rotation_deg = t.rotation_rad * 180.0 / 3.14159265358979323846;
      s.hand_mN = t.hand_force_mN;
      const std::size_t n = t.positions_mm.size();
      const std::size_t step = std::max<std::size_t>(1, (n + kTraceNodes - 2) / (kTraceNodes - 1));
      for (std::size_t i = 0; i < n; i += step) push_node(s, t.positions_mm[i]);
      if (n > 0 && (n - 1) % step != 0) push_node(s, t.positions_mm[n - 1]);
    }
    samples_.push_back(std::move(s));
  }

  // {"format","period_ms","tools","target_mm","t_ms","tip_mm","insertion_mm","rotation_deg",
  //  "hand_mN","wall_peak_mN","fluoro","nodes_mm","events"} and, in a thrombectomy case,
  // "retrieval_mN" (the peak stent pull since the last sample): columns, one entry per sample
  // (tip_mm flat x,y,z; nodes_mm one flat array per sample).
  [[nodiscard]] std::string json(const session::SessionCase& scene) const {
    const std::size_t k = (samples_.size() + kMaxTraceSamples - 1) / kMaxTraceSamples;
    const std::size_t stride = std::max<std::size_t>(k, 1);
    nlohmann::json t_ms = nlohmann::json::array(), tip = nlohmann::json::array(), ins = nlohmann::json::array(),
                   rot = nlohmann::json::array(), hand = nlohmann::json::array(), wall = nlohmann::json::array(),
                   fluoro = nlohmann::json::array(), nodes = nlohmann::json::array(), retrieval = nlohmann::json::array();
    for (std::size_t i = 0; i < samples_.size(); i += stride) {
      const Sample& s = samples_[i];
      double peak = 0.0;
      double pull = 0.0;
      for (std::size_t j = i; j < std::min(i + stride, samples_.size()); ++j) {
        peak = std::max(peak, samples_[j].wall_peak_mN);
        pull = std::max(pull, samples_[j].retrieval_mN);
      }
      t_ms.push_back(static_cast<double>(s.t_us) / 1000.0);
      for (int a = 0; a < 3; ++a) tip.push_back(r2(s.tip[a]));
      ins.push_back(r2(s.insertion_mm));
      rot.push_back(r2(s.rotation_deg));
      hand.push_back(r2(s.hand_mN));
      wall.push_back(r2(peak));
      retrieval.push_back(r2(pull));
      fluoro.push_back(s.fluoro ? 1 : 0);
      nodes.push_back(s.nodes);
    }
    nlohmann::json events = nlohmann::json::array();
    for (const Event& e : events_) events.push_back(event_json(e));
    nlohmann::json tools = nlohmann::json::array();
    for (const std::string& name : tools_) tools.push_back(name);
    nlohmann::json out = {{"format", "cathbox-trace 2"},
                          {"period_ms", static_cast<double>(kTracePeriod_us * static_cast<std::int64_t>(stride)) / 1000.0},
                          {"samples", t_ms.size()},
                          {"tools", std::move(tools)},
                          {"target_mm", nullptr},
                          {"target_radius_mm", scene.target_radius_mm},
                          {"t_ms", std::move(t_ms)},
                          {"tip_mm", std::move(tip)},
                          {"insertion_mm", std::move(ins)},
                          {"rotation_deg", std::move(rot)},
                          {"hand_mN", std::move(hand)},
                          {"wall_peak_mN", std::move(wall)},
                          {"fluoro", std::move(fluoro)},
                          {"nodes_mm", std::move(nodes)},
                          {"events", std::move(events)},
                          {"events_dropped", events_dropped_}};
    if (last_.thrombectomy) out["retrieval_mN"] = std::move(retrieval);
    if (scene.target_mm) out["target_mm"] = {r2(scene.target_mm->x), r2(scene.target_mm->y), r2(scene.target_mm->z)};
    return out.dump();
  }

 private:
  // A pass (its eTICI as the metrics give it at the end: an embolus lodging later grades the
  // pass again) and a lodged embolus (the segment it lodged in, whether a new territory).
  [[nodiscard]] nlohmann::json event_json(const Event& e) const {
    nlohmann::json j = {{"t_ms", static_cast<double>(e.t_us) / 1000.0}, {"kind", e.kind}};
    if (e.index == 0 || !last_.thrombectomy) return j;
    const session::ThrombectomyFigures& t = *last_.thrombectomy;
    const auto k = static_cast<std::size_t>(e.index - 1);
    if (std::string_view(e.kind) == "pass") {
      j["pass"] = e.index;
      if (k < session::ThrombectomyFigures::kMaxPasses) {
        j["etici"] = std::string(flow::etici_label(t.etici_after_pass[k]));
        j["reperfused_pct"] = r2(t.reperfused_pct_after_pass[k]);
      }
    } else {
      j["embolus"] = e.index;
      if (k < t.emboli_lodged.size()) j["segment"] = t.emboli_lodged[k];
      if (k < embolus_new_territory_.size()) j["new_territory"] = embolus_new_territory_[k] != 0;
    }
    return j;
  }
  // A pass ends, an embolus lodges: where the thrombectomy figures' counters move.
  void thrombectomy_events(std::int64_t t_us, const session::Metrics& m) {
    if (!m.thrombectomy || !last_.thrombectomy) return;
    const session::ThrombectomyFigures& now = *m.thrombectomy;
    const session::ThrombectomyFigures& before = *last_.thrombectomy;
    for (int p = before.passes + 1; p <= now.passes; ++p) event(t_us, "pass", p);
    const bool new_territory = now.emboli_new_territory > before.emboli_new_territory;
    for (int e = before.emboli + 1; e <= now.emboli; ++e) {
      embolus_new_territory_.push_back(new_territory ? 1 : 0);
      event(t_us, "embolus", e);
    }
  }
  static void push_node(Sample& s, const glm::dvec3& p) {
    for (int a = 0; a < 3; ++a) s.nodes.push_back(r2(p[a]));
  }
  void event(std::int64_t t_us, const char* kind, int index = 0) {
    if (events_.size() < kMaxTraceEvents) events_.push_back({t_us, kind, index});
    else ++events_dropped_;
  }

  std::vector<Sample> samples_;
  std::vector<Event> events_;
  std::vector<std::string> tools_;
  std::int64_t events_dropped_ = 0;
  session::Metrics last_;
  bool started_ = false;
  bool fluoro_ = false;
  double interval_wall_ = 0.0;
  double interval_retrieval_ = 0.0;
  std::vector<std::uint8_t> embolus_new_territory_;  // per embolus marked
};

class SessionChecker final : public RecordChecker {
 public:
  explicit SessionChecker(UploadLimits limits) : limits_(std::move(limits)) {
    if (!limits_.cpu_seconds) limits_.cpu_seconds = thread_cpu_seconds;
  }

  Result<CheckedRecord> check(std::string_view bytes) override {
    // Before anything is meshed or simulated: the run's length and hash (ticks decoded only),
    // the tools against the case text, the vessel's size.
    Result<RecordScan> scan = scan_record(bytes, limits_);
    if (!scan) return scan.error();
    TraceObserver observer;  // the debrief's trace comes from this same replay
    Result<std::unique_ptr<session::Replay>> replay = open(bytes, observer);
    if (!replay) return replay.error();
    session::Replay& run = *replay.value();
    if (Status s = check_header_entry(run.header(), run.session().scene()); !s) return s.error();
    if (Status s = step_within_budget(run); !s) return s.error();
    const session::ReplayResult r = run.result();
    if (!r.error.empty()) return make_error(422, r.error);
    if (r.mismatch) {
      return make_error(422, "record: tick " + std::to_string(r.mismatch->tick) +
                                 ": state hash differs (tampered or broken)");
    }
    if (r.hashes_checked == 0) return make_error(422, "record: no state hash to check (shorter than one hash interval)");
    const session::RecordHeader& h = run.header();
    CheckedRecord out;
    // The library names files plainly (a case names its HCLM by its plain name); a record keeps
    // the paths they were opened from.
    out.case_files.case_file = std::filesystem::path(h.case_file).filename().string();
    out.case_files.case_text = h.case_text;
    out.case_files.hclm_file = std::filesystem::path(h.vessel_file).filename().string();
    out.case_files.hclm_text = h.vessel_text;
    out.case_files.surface_file = std::filesystem::path(h.surface_file).filename().string();
    out.case_files.surface_bytes = h.surface_bytes;
    out.case_title = h.case_name;
    out.started_us = h.start_unix_us;
    out.duration_ms = r.ticks * h.period_us / 1000;
    out.complete = r.end.has_value();
    out.run_hash = scan.value().run_hash;
    for (const session::NamedMetric& m : session::named_metrics(r.metrics)) out.metrics.push_back({m.name, m.value});
    out.trace = observer.json(run.session().scene());
    return out;
  }

  Result<std::string> trace(std::string_view bytes) override {
    TraceObserver observer;
    Result<std::unique_ptr<session::Replay>> replay = open(bytes, observer);
    if (!replay) return replay.error();
    if (Status s = step_within_budget(*replay.value()); !s) return s.error();
    const session::ReplayResult r = replay.value()->result();
    if (!r.matched()) return make_error(422, r.error.empty() ? "record: state hash differs on replay" : r.error);
    return observer.json(replay.value()->session().scene());
  }

 private:
  // The replay, its vessel meshed, once the header's tools and the vessel's size passed.
  Result<std::unique_ptr<session::Replay>> open(std::string_view bytes, TraceObserver& observer) const {
    auto reader = session::RecordReader::from_bytes(std::vector<std::uint8_t>(bytes.begin(), bytes.end()), "record");
    if (!reader) return make_error(422, reader.error().message);
    const session::RecordHeader& h = (*reader)->header();
    if (Status s = check_header_tools(h); !s) return s.error();
    const std::string vessel = std::filesystem::path(h.vessel_file).filename().string();
    if (Status s = check_vessel_bounds(h.vessel_text, "record: " + (vessel.empty() ? std::string("vessel") : vessel), limits_); !s) {
      return s.error();
    }
    auto replay = session::Replay::open(std::move(*reader));
    if (!replay) return make_error(422, replay.error().message);
    (*replay)->session().add_observer(observer);
    return std::move(*replay);
  }

  // Runs the replay to its end, 1,000 ticks at a time, within the CPU budget.
  Status step_within_budget(session::Replay& replay) const {
    const double start_s = limits_.cpu_seconds();
    while (!replay.done()) {
      replay.step(kBudgetTicks);
      const double used_s = limits_.cpu_seconds() - start_s;
      if (used_s > limits_.max_replay_cpu_s) {
        return make_error(413, "record: the replay passed its CPU limit of " + std::to_string(static_cast<std::int64_t>(limits_.max_replay_cpu_s)) +
                                   " s at tick " + std::to_string(replay.session().ticks()));
      }
    }
    return Ok{};
  }

  static constexpr std::int64_t kBudgetTicks = 1000;
  UploadLimits limits_;

 public:
  [[nodiscard]] std::vector<std::string> metric_names() const override { return session::metric_names(); }
};

}  // namespace

std::unique_ptr<RecordChecker> make_session_checker(UploadLimits limits) { return std::make_unique<SessionChecker>(std::move(limits)); }

}  // namespace cathbox::server
