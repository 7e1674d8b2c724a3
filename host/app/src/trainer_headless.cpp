// cathbox-trainer without a window: a run of the default case by the scripted hand in virtual
// time (through the box in real time with --emu or --box), or the replay of a record, each printing its events and the end-of-run figures.
#include <cstdio>

#include "app/trainer_app.hpp"
#include "app/server_link.hpp"
#include "device/clock.hpp"
#include "app/trainer_launch.hpp"
#include "base/exit_codes.hpp"

namespace cathbox::app {
namespace {
constexpr int kStreamConnect_ms = 5000;
}  // namespace

int TrainerApp::run_headless_summary() {
  const CaseChoice choice = choose();
  if (choice.path.empty()) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", choice.error.c_str());
    return base::kExitBadInput;
  }
  if (const base::Status<> opened = open_live(choice.path); !opened) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", opened.error().message.c_str());
    return base::kExitBadInput;
  }
  const bool through_box = !scripted_ && options_.script.empty();
  std::printf("cathbox-trainer: headless run of %s with the %s (%s)\n", live_->scene().name.c_str(),
              options_.script.empty() && scripted_ ? "scripted hand" : live_->hand_description().c_str(),
              through_box ? "real time" : "virtual time");
  if (!record_path_.empty()) std::fprintf(stderr, "cathbox-trainer: recording to %s\n", record_path_.c_str());
  if (link_) {
    // Instructors should see the run at all: it runs in virtual time, faster than real time.
    const bool streaming = link_->wait_streaming(kStreamConnect_ms);
    std::printf("cathbox-trainer: %s live%s\n", streaming ? "streaming" : "not streaming",
                live_assignment_ ? (" (assignment " + std::to_string(*live_assignment_) + ")").c_str() : "");
  }
  const std::int64_t limit_ticks =
      options_.max_seconds > 0.0 ? static_cast<std::int64_t>(options_.max_seconds * 1000.0) : -1;
  session::LogEvent e;
  // --speed: each frame waits for its wall time, so watchers see the run as a rig streams it.
  device::SystemClock clock;
  const std::int64_t start_us = clock.now_us();
  // A box runs in real time: the session's haptic thread drives it, this loop only watches.
  const bool real_time = !scripted_ && options_.script.empty();
  if (real_time) live_->start();
  // Steps of one live frame (33 ticks: ~30 frames per simulated second).
  while (!live_->over() && (limit_ticks < 0 || live_->ticks() < limit_ticks)) {
    if (real_time) {
      clock.sleep_until_us(clock.now_us() + 33'000);
    } else {
      live_->step_virtual(33);
    }
    if (!real_time && options_.speed > 0.0)
      clock.sleep_until_us(start_us + static_cast<std::int64_t>(static_cast<double>(live_->ticks()) * 1000.0 / options_.speed));
    while (live_->events().pop(e)) std::printf("%8.3f s  %s\n", static_cast<double>(e.time_us) * 1e-6, e.text.data());
    if (link_) {
      live_->snapshots().acquire();
      link_->publish(live_->snapshots().read_slot());
    }
  }
  if (real_time) {
    live_->stop();
    std::printf("cathbox-trainer: %lld haptic ticks in real time, %lld dropped\n", static_cast<long long>(live_->ticks()),
                static_cast<long long>(live_->dropped_ticks()));
  }
  live_->end_run();
  live_->step_virtual(1);
  std::printf("end of run\n%s", session::MetricsCollector::format(live_->metrics()).c_str());
  if (link_) {
    close_live(false);
    const server::FlushReport u = link_->flush_now();
    std::printf("upload: %d stored, %d already on the server, %d refused, %d queued%s%s\n", u.stored, u.duplicates, u.refused,
                u.left, u.stopped_by.empty() ? "" : ": ", u.stopped_by.c_str());
  }
  return base::kExitOk;
}

int TrainerApp::run_headless_replay() {
  if (const base::Status<> opened = open_replay(options_.replay); !opened) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", opened.error().message.c_str());
    return base::kExitBadInput;
  }
  std::printf("cathbox-trainer: replay of %s (%s)\n", options_.replay.c_str(), replay_->header().case_name.c_str());
  replay_->seek(replay_->total_ticks());
  (void)replay_->advance(0, -1);
  const session::ReplayResult r = replay_->replay().result();
  std::printf("end of replay: %lld ticks, %lld state hashes checked%s\n%s", static_cast<long long>(r.ticks),
              static_cast<long long>(r.hashes_checked), r.mismatch ? ", MISMATCH" : "",
              session::MetricsCollector::format(r.metrics).c_str());
  return r.mismatch ? base::kExitFailure : base::kExitOk;
}

}  // namespace cathbox::app
