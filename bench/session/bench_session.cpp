// bench_session: what the session costs per 1 kHz tick on top of the simulation, and how fast a
// record replays.
//  - SessionTick/<case>: the same action script drives a Session (hand, mapping, record, state
//    hashes, metrics, snapshot, events) and, in lockstep, a bare tool::Simulator given the
//    session's inputs. Per tick: the session's tick, the bare step, and their difference (the
//    session's overhead). Median and p99 of each as counters. SessionTick/neuro_contrast: the same
//    under fluoroscopy with contrast injected (the fluoroscopy unit and its 100 Hz transport).
//    tick_cpu_*: the tick's thread CPU time (less sensitive to other processes than wall time).
//  - Recording: Recorder calls for one tick of a moving hand (two tools, a hash every 100 ticks),
//    compression and writing on its own thread as in a run.
//  - Replay/<minutes>: a record of a run made by an action script in virtual time is replayed
//    with every state hash checked; counter x_real_time = recorded seconds / replay seconds.
//  - RealTimeTicks/<seconds>: the haptic thread in real time; the interval between ticks (p50,
//    p99, max; the label: the scheduling the OS granted), beside the trainee page's worker clock
//    (scripts/bench train, which also runs it without CAP_SYS_NICE: a normal-priority thread).
//  - CaseAtRigSpeed/<case>: a bundled case driven by its own action script through the haptic
//    thread's loop (HapticThread::run, its pacer: up to 4 late ticks caught up, the rest dropped)
//    on a clock that moves by each tick's thread CPU time and, when the loop waits for its next
//    deadline, by that wait in real time (RigClock: the released coils' job, on the other core,
//    runs on through it as on a rig): what a rig whose haptic thread has a core of this machine
//    to itself would run (no other process; the rig's heap policy, session/haptic_memory.hpp). Per
//    tick: median, p99, max CPU; ticks over the 1 ms budget; ticks the pacer dropped; the latest
//    a tick started; the second of the run with the most ticks over budget; the released coils'
//    steps skipped asleep and their wakes; page faults in the ticks. The ten slowest ticks (case
//    time, CPU), the dropped and the over-budget ticks by second of the case, and the over-budget
//    ticks' CPU by solve (tick_solves.hpp: each rod by the sub-increments its solve ended in) go
//    to stderr. The released coils' job runs on the other core (the haptic thread spins while it
//    waits: its CPU time is the tick's). Opt-in (scripts/bench session): each case takes about
//    its own length in real time (the dense coiling case ~65 s).
//  - FirstTickAfterImport: issue 31's "first frame <= 2 s after import". Once, untimed: the
//    head-and-neck tree (cases/library/ica_straight.hclm) meshed with 10 points per ring (293k
//    triangles) as STL, imported as a surface and written as `cathbox vessel import -o CASE_DIR`
//    writes it (vessel.hclm, lumen.cbxmesh, a case naming both, `flow terminals fixed`). Timed:
//    loading that case (graph, lumen, collision tree, flow), the session, and its first tick.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "session/action_script_hand.hpp"
#include "session/clock.hpp"
#include "session/haptic_memory.hpp"
#include "session/haptic_thread.hpp"
#include "session/recorder.hpp"
#include "session/replay.hpp"
#include "session/session.hpp"
#include "vessel/hclm.hpp"
#include "vessel/mesh_export.hpp"
#include "vessel/vessel_mesher.hpp"
#include "vessel_import/importer.hpp"
#include "scenario/case_file.hpp"
#include "tool/simulator.hpp"
#include "../bench_samples.hpp"
#include "tick_solves.hpp"

namespace {

using cathbox::session::ActionScriptHand;
using cathbox::session::Session;
using cathbox::session::SessionOptions;
using cathbox::session::TickInput;
using cathbox::session::TickObserver;
using cathbox::session::TickView;
using Clock = std::chrono::steady_clock;

std::string scratch(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "cathbox_bench_session";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

using cathbox::bench::thread_cpu_us;
// This program's counters keep the rank floor(q (n - 1)).
double percentile(const std::vector<double>& v, double q) { return cathbox::bench::quantile_below(v, q); }

// Pushes in and pulls back with a full turn of the tip each way, for `minutes`. With `contrast`,
// every 10 s cycle also has the pedal down from 0.5 to 8 s and 6 mL injected at 6 mL/s at 1 s
// (from the first tool, the catheter in neuro), so contrast flows most of the time.
std::string write_script(const std::string& name, int minutes, bool contrast = false) {
  const std::string path = scratch(name);
  std::ofstream out(path);
  for (int cycle = 0; cycle < minutes * 6; ++cycle) {
    const int t0 = cycle * 10'000;
    out << t0 << " insert_to 80 at 25\n";
    if (contrast) out << t0 + 500 << " fluoro on\n";
    out << t0 + 1000 << " rotate_by 360 at 180\n";
    if (contrast) out << t0 + 1000 << " inject 6 at 6\n";
    out << t0 + 5000 << " insert_to 30 at 25\n" << t0 + 6000 << " rotate_by -360 at 180\n";
    if (contrast) out << t0 + 8000 << " fluoro off\n";
  }
  out << minutes * 60'000 << " end\n";
  return path;
}

std::unique_ptr<Session> open_session(const std::string& case_path, const std::string& script, std::string& error) {
  auto scene = cathbox::session::load_session_case(case_path);
  if (!scene) {
    error = scene.error().message;
    return nullptr;
  }
  auto hand = ActionScriptHand::load(script, *scene.value());
  if (!hand) {
    error = hand.error().message;
    return nullptr;
  }
  return std::make_unique<Session>(std::move(scene.value()), std::move(*hand), SessionOptions{});
}

// Copies the inputs the session gave its simulator at each tick.
struct InputTap final : TickObserver {
  TickInput input;
  void observe(const TickView& view) override { input = view.input; }
};

void SessionTick(benchmark::State& state, const std::string& case_name, bool contrast) {
  const std::string case_path = std::string(CATHBOX_SOURCE_DIR) + "/cases/" + case_name + ".case";
  const std::string script = write_script("tick.actions", 1, contrast);
  std::string error;
  auto session = open_session(case_path, script, error);
  auto bare_scene = cathbox::session::load_session_case(case_path);
  if (!session || !bare_scene) {
    state.SkipWithError((error.empty() ? bare_scene.error().message : error).c_str());
    return;
  }
  if (const cathbox::base::Status<> recording = session->record_to(scratch("tick.cbxrec")); !recording) {
    state.SkipWithError(recording.error().message.c_str());
    return;
  }
  cathbox::tool::Simulator bare(bare_scene.value()->world->wall(), bare_scene.value()->spec.tools, bare_scene.value()->entry);
  InputTap tap;
  session->add_observer(tap);
  constexpr double kDt = 1e-3;
  std::vector<double> tick_us;
  std::vector<double> tick_cpu_us;
  std::vector<double> step_us;
  std::vector<double> overhead_us;
  for (auto _ : state) {
    const double c0 = thread_cpu_us();
    const auto t0 = Clock::now();
    session->step_virtual(1);
    const auto t1 = Clock::now();
    tick_cpu_us.push_back(thread_cpu_us() - c0);
    for (std::size_t t = 0; t < tap.input.tool_count; ++t) {
      bare.set_insertion(t, static_cast<double>(tap.input.tools[t].insertion_um) * 1e-3);
      bare.set_rotation(t, static_cast<double>(tap.input.tools[t].rotation_urad) * 1e-6);
    }
    bare.step(kDt);
    const auto t2 = Clock::now();
    const double a = std::chrono::duration<double, std::micro>(t1 - t0).count();
    const double b = std::chrono::duration<double, std::micro>(t2 - t1).count();
    tick_us.push_back(a);
    step_us.push_back(b);
    overhead_us.push_back(a - b);
    if (session->over()) break;
  }
  session->stop();
  state.counters["tick_median_us"] = percentile(tick_us, 0.5);
  state.counters["tick_p99_us"] = percentile(tick_us, 0.99);
  state.counters["sim_step_median_us"] = percentile(step_us, 0.5);
  state.counters["sim_step_p99_us"] = percentile(step_us, 0.99);
  state.counters["overhead_median_us"] = percentile(overhead_us, 0.5);
  state.counters["overhead_p99_us"] = percentile(overhead_us, 0.99);
  state.counters["tick_max_us"] = percentile(tick_us, 1.0);
  // The tick's own CPU time: what the figures are without the other processes' preemption.
  state.counters["tick_cpu_median_us"] = percentile(tick_cpu_us, 0.5);
  state.counters["tick_cpu_p99_us"] = percentile(tick_cpu_us, 0.99);
  if (const auto* fluoro = session->fluoro(); contrast && fluoro != nullptr) {
    state.counters["contrast_ml"] = fluoro->transport().injected_volume_ml();
    state.counters["pulses"] = static_cast<double>(fluoro->fluoroscope().metrics().pulses);
  }
}
BENCHMARK_CAPTURE(SessionTick, y_bifurcation, std::string("y_bifurcation"), false)->Iterations(20'000)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(SessionTick, neuro, std::string("neuro"), false)->Iterations(20'000)->Unit(benchmark::kMicrosecond);
// The same with the pedal down and contrast flowing: the fluoroscopy unit and the 100 Hz
// transport step on the haptic thread.
BENCHMARK_CAPTURE(SessionTick, neuro_contrast, std::string("neuro"), true)->Iterations(20'000)->Unit(benchmark::kMicrosecond);

void Recording(benchmark::State& state) {
  cathbox::session::RecordHeader header;
  header.case_name = "bench";
  header.tools = {cathbox::tool::default_catheter(), cathbox::tool::default_guidewire()};
  auto created = cathbox::session::Recorder::create(scratch("recording.cbxrec"), header);
  if (!created) {
    state.SkipWithError(created.error().message.c_str());
    return;
  }
  auto& rec = *created;
  TickInput in;
  in.tool_count = 2;
  std::int64_t tick = 0;
  std::vector<double> samples_us;
  samples_us.reserve(1 << 20);
  for (auto _ : state) {
    const auto t0 = Clock::now();
    rec->begin_tick(tick, tick * 1000);
    in.tools[1].insertion_um += 9 + (tick % 3);
    in.tools[1].rotation_urad -= (tick % 50 == 0) ? 1534 : 0;
    if (tick % 7 == 0) in.tools[0].insertion_um += 9;
    rec->tools(in);
    rec->box({true, true, 0});
    if ((tick + 1) % 100 == 0) rec->state_hash(0x9e3779b97f4a7c15ULL * static_cast<std::uint64_t>(tick));
    rec->end_tick();
    samples_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    ++tick;
  }
  rec->finish(cathbox::session::record::EndReason::kEndedByUser, "bench", tick, 0);
  if (!rec->close()) state.SkipWithError(rec->error().c_str());
  state.counters["median_us"] = percentile(samples_us, 0.5);
  state.counters["p99_us"] = percentile(samples_us, 0.99);
  state.counters["bytes_per_tick"] = static_cast<double>(rec->bytes_written()) / static_cast<double>(std::max<std::int64_t>(tick, 1));
}
// The ten slowest ticks of a run (their case time and CPU time), on stderr: where to look first.
void print_slowest_ticks(const std::string& case_name, const std::vector<double>& cpu_us,
                         const std::vector<std::int64_t>& tick_at_us) {
  std::vector<std::size_t> order(cpu_us.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const std::size_t shown = std::min<std::size_t>(10, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(shown), order.end(),
                    [&](std::size_t a, std::size_t b) { return cpu_us[a] > cpu_us[b]; });
  std::fprintf(stderr, "%s: slowest ticks (case time s: CPU us):", case_name.c_str());
  for (std::size_t i = 0; i < shown; ++i) {
    std::fprintf(stderr, " %.3f: %.0f", 1e-6 * static_cast<double>(tick_at_us[order[i]]), cpu_us[order[i]]);
  }
  std::fprintf(stderr, "\n");
}

// The seconds of the case with a count, as "second: count".
void print_seconds(const std::string& case_name, const char* what, const std::vector<int>& per_second) {
  std::fprintf(stderr, "%s: %s (s: n):", case_name.c_str(), what);
  for (std::size_t s = 0; s < per_second.size(); ++s) {
    if (per_second[s] > 0) std::fprintf(stderr, " %zu: %d", s, per_second[s]);
  }
  std::fprintf(stderr, "\n");
}

// CaseAtRigSpeed's clock: a rig's haptic thread with one core to itself. Time moves by the
// thread's CPU time while it works (advance_us, after each tick) and by real time while it waits
// for its next tick (sleep_until_us waits that long on the steady clock), so the released coils'
// job, on the other core, runs on through the wait as on a rig (Simulator::set_released_overlap;
// a tick that waits for it spins, and its thread CPU time carries the wait).
class RigClock final : public cathbox::session::Clock {
 public:
  [[nodiscard]] std::int64_t now_us() override { return now_.load(std::memory_order_acquire); }
  void sleep_until_us(std::int64_t deadline_us) override {
    const std::int64_t now = now_us();
    if (deadline_us <= now) return;
    // Asleep as the rig's thread would be (its core free for the record's writer), then spinning
    // the last stretch a sleep may overshoot.
    const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(deadline_us - now);
    std::this_thread::sleep_until(until - std::chrono::microseconds(kSpin_us));
    while (std::chrono::steady_clock::now() < until) {
    }
    now_.store(deadline_us, std::memory_order_release);
  }
  void wait(int /*fd*/, std::int64_t max_us) override { sleep_until_us(now_us() + max_us); }
  void advance_us(std::int64_t us) { now_.fetch_add(us, std::memory_order_acq_rel); }

 private:
  static constexpr std::int64_t kSpin_us = 100;
  std::atomic<std::int64_t> now_{0};
};

void CaseAtRigSpeed(benchmark::State& state, const std::string& case_name) {
  cathbox::session::keep_freed_memory();  // as HapticThread::start() sets it on a rig
  const std::string base = std::string(CATHBOX_SOURCE_DIR) + "/cases/" + case_name;
  for (auto _ : state) {
    std::string error;
    auto session = open_session(base + ".case", base + ".actions", error);
    if (!session) {
      state.SkipWithError(error.c_str());
      return;
    }
    constexpr std::int64_t kPeriod_us = 1000;
    RigClock clock;
    std::vector<double> cpu_us;
    std::vector<std::int64_t> tick_at_us;
    std::vector<int> over_per_second, dropped_per_second;
    std::int64_t behind_us = 0, dropped_seen = 0;
    long faults_over = 0, faults_all = 0;
    cathbox::bench::TickSolves solves;
    session->set_solve_observer(&solves);
    cathbox::session::HapticThread loop(clock, kPeriod_us, [&](std::int64_t sim_us) {
      // How late this tick starts on its deadline (the dropped ticks' deadlines skipped).
      behind_us = std::max(behind_us, clock.now_us() - (sim_us + loop.dropped() * kPeriod_us));
      const long faults0 = cathbox::bench::thread_usage().faults;
      solves.begin_tick();
      const double c0 = thread_cpu_us();
      session->step_virtual(1);
      const double used = thread_cpu_us() - c0;
      solves.end_tick(used, static_cast<double>(kPeriod_us));
      const long faults = cathbox::bench::thread_usage().faults - faults0;
      faults_all += faults;
      if (used > static_cast<double>(kPeriod_us)) faults_over += faults;
      cpu_us.push_back(used);
      tick_at_us.push_back(sim_us);
      const auto second = static_cast<std::size_t>(sim_us / 1'000'000);
      if (over_per_second.size() <= second) {
        over_per_second.resize(second + 1, 0);
        dropped_per_second.resize(second + 1, 0);
      }
      if (used > static_cast<double>(kPeriod_us)) ++over_per_second[second];
      // The deadlines the pacer skipped before this tick, on the second they fell in.
      dropped_per_second[second] += static_cast<int>(loop.dropped() - dropped_seen);
      dropped_seen = loop.dropped();
      clock.advance_us(static_cast<std::int64_t>(used));
      return !session->over();
    });
    loop.run(cathbox::base::stop_token{});
    session->stop();
    const auto worst = std::max_element(over_per_second.begin(), over_per_second.end());
    state.counters["ticks"] = static_cast<double>(cpu_us.size());
    state.counters["tick_cpu_median_us"] = percentile(cpu_us, 0.5);
    state.counters["tick_cpu_p99_us"] = percentile(cpu_us, 0.99);
    state.counters["tick_cpu_max_us"] = percentile(cpu_us, 1.0);
    state.counters["over_1ms"] = static_cast<double>(std::count_if(cpu_us.begin(), cpu_us.end(), [](double us) { return us > 1000.0; }));
    state.counters["dropped"] = static_cast<double>(loop.dropped());
    // Page faults taken in the ticks (a fresh page costs a fault and its zeroing), and in those
    // over the budget.
    state.counters["faults"] = static_cast<double>(faults_all);
    state.counters["faults_over_1ms"] = static_cast<double>(faults_over);
    state.counters["late_max_ms"] = static_cast<double>(behind_us) * 1e-3;
    state.counters["worst_second"] = worst == over_per_second.end() ? 0.0 : static_cast<double>(worst - over_per_second.begin());
    state.counters["worst_second_over_1ms"] = worst == over_per_second.end() ? 0.0 : *worst;
    // Released coils' steps skipped asleep (tool/coil_sleep.hpp), and their wakes.
    const cathbox::tool::CoilSleep& sleep = session->simulator().coil_sleep();
    state.counters["coil_steps_asleep"] = static_cast<double>(sleep.skipped_steps());
    state.counters["coil_wakes"] = static_cast<double>(sleep.wakes());
    print_slowest_ticks(case_name, cpu_us, tick_at_us);
    print_seconds(case_name, "dropped ticks by second of the case", dropped_per_second);
    print_seconds(case_name, "ticks over 1 ms by second of the case", over_per_second);
    solves.report(state, case_name, session->simulator());
  }
}
BENCHMARK_CAPTURE(CaseAtRigSpeed, neuro_coiling, std::string("neuro_coiling"))->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(CaseAtRigSpeed, neuro_coiling_dense, std::string("neuro_coiling_dense"))->Iterations(1)->Unit(benchmark::kSecond);

// The imported case folder (see the header); empty with `error` set when a step failed.
std::string imported_case(std::string& error) {
  const auto read = cathbox::vessel::load_hclm(std::string(CATHBOX_SOURCE_DIR) + "/cases/library/ica_straight.hclm");
  cathbox::vessel::MeshOptions options;
  options.ring_points = 10;
  const cathbox::vessel::VesselSurface surface = build_vessel_surface(read.model, options);
  const std::string stl = scratch("import300k.stl");
  if (!surface.ok() || !cathbox::vessel::write_mesh(surface.mesh, stl).empty()) {
    error = "could not mesh or write the surface";
    return {};
  }
  const cathbox::vessel_import::ImportResult imported = cathbox::vessel_import::import_centerlines(stl);
  std::filesystem::remove(stl);
  if (!imported.ok()) {
    error = imported.errors.front().to_string();
    return {};
  }
  error = cathbox::vessel::save_hclm(imported.model, scratch("vessel.hclm"));
  if (error.empty()) error = cathbox::vessel::write_mesh(imported.lumen, scratch("lumen.cbxmesh"));
  std::ofstream(scratch("import300k.case"))
      << "cathbox-case 1\nname import300k\nvessel vessel.hclm\nsurface lumen.cbxmesh\nflow terminals fixed\n";
  return error.empty() ? scratch("import300k.case") : std::string();
}

void FirstTickAfterImport(benchmark::State& state) {
  std::string error;
  const std::string case_path = imported_case(error);
  const std::string script = write_script("first.actions", 1);
  std::vector<double> cpu_s;
  for (auto _ : state) {
    const double c0 = thread_cpu_us();
    auto session = open_session(case_path, script, error);
    if (!session) {
      state.SkipWithError(error.c_str());
      return;
    }
    const std::int64_t ran = session->step_virtual(1);
    cpu_s.push_back((thread_cpu_us() - c0) * 1e-6);
    if (ran != 1) state.SkipWithError("the session did not tick");
  }
  state.counters["cpu_s"] = cpu_s.empty() ? 0.0 : percentile(cpu_s, 0.5);
  for (const char* name : {"vessel.hclm", "lumen.cbxmesh", "import300k.case"}) std::filesystem::remove(scratch(name));
}

BENCHMARK(FirstTickAfterImport)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(Recording)->Iterations(600'000)->Unit(benchmark::kMicrosecond);

void Replay(benchmark::State& state) {
  const int minutes = static_cast<int>(state.range(0));
  const std::string case_path = std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation.case";
  const std::string script = write_script("replay.actions", minutes);
  const std::string record = scratch("replay.cbxrec");
  std::string error;
  auto session = open_session(case_path, script, error);
  if (!session) {
    state.SkipWithError(error.c_str());
    return;
  }
  if (const cathbox::base::Status<> recording = session->record_to(record); !recording) {
    state.SkipWithError(recording.error().message.c_str());
    return;
  }
  while (!session->over()) session->step_virtual(10'000);
  if (!session->recorder()->close()) {
    state.SkipWithError(session->recorder()->error().c_str());
    return;
  }
  const double recorded_s = static_cast<double>(session->ticks()) * 1e-3;
  double replay_s = 0.0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    const cathbox::session::ReplayResult r = cathbox::session::replay_record(record);
    replay_s = std::chrono::duration<double>(Clock::now() - t0).count();
    if (!r.matched()) {
      state.SkipWithError(r.error.empty() ? "a state hash differs" : r.error.c_str());
      return;
    }
  }
  state.counters["recorded_s"] = recorded_s;
  state.counters["replay_s"] = replay_s;
  state.counters["x_real_time"] = recorded_s / replay_s;
  state.counters["record_bytes"] = static_cast<double>(std::filesystem::file_size(record));
}
BENCHMARK(Replay)->Arg(10)->Iterations(1)->Unit(benchmark::kSecond);

// The native haptic thread in real time: the interval between consecutive ticks as they ran
// (steady clock, taken by an observer on the haptic thread), over `seconds` of the y_bifurcation
// script. The figure the trainee page's Web Worker clock is compared with (scripts/bench train).
class TickTimes final : public TickObserver {
 public:
  explicit TickTimes(std::size_t n) { at_.reserve(n); }
  void observe(const TickView&) override {
    if (at_.size() < at_.capacity()) at_.push_back(Clock::now());
  }
  [[nodiscard]] std::vector<double> intervals_ms() const {
    std::vector<double> out;
    for (std::size_t i = 1; i < at_.size(); ++i) out.push_back(std::chrono::duration<double, std::milli>(at_[i] - at_[i - 1]).count());
    return out;
  }

 private:
  std::vector<Clock::time_point> at_;
};

void RealTimeTicks(benchmark::State& state) {
  const int seconds = static_cast<int>(state.range(0));
  const std::string case_path = std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation.case";
  const std::string script = scratch("realtime.actions");
  std::ofstream(script) << "0 insert_to 40 at 30\n1400 rotate_to 360 at 180\n2500 insert_to 80 at 10\n" << seconds * 1000 << " end\n";
  for (auto _ : state) {
    std::string error;
    auto session = open_session(case_path, script, error);
    if (!session) {
      state.SkipWithError(error.c_str());
      return;
    }
    TickTimes times(static_cast<std::size_t>(seconds) * 1000 + 100);
    session->add_observer(times);
    session->start();
    while (!session->over()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    session->stop();
    state.SetLabel(session->haptic_scheduling());  // SCHED_FIFO, nice, or normal: what the OS granted
    const std::vector<double> intervals = times.intervals_ms();
    state.counters["ticks"] = static_cast<double>(session->ticks());
    state.counters["interval_p50_ms"] = cathbox::bench::quantile(intervals, 0.5);
    state.counters["interval_p99_ms"] = cathbox::bench::quantile(intervals, 0.99);
    state.counters["interval_max_ms"] = cathbox::bench::quantile(intervals, 1.0);
    state.counters["dropped"] = static_cast<double>(session->dropped_ticks());
  }
}
BENCHMARK(RealTimeTicks)->Arg(5)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
