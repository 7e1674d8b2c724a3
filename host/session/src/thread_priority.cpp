#include "session/thread_priority.hpp"

#if defined(__EMSCRIPTEN__)
// The browser (or node) schedules its workers itself: nothing to ask for, nothing to lower.
namespace cathbox::session {

void ThreadPriority::tighten_timer_slack() {}
HapticScheduling ThreadPriority::favour_calling_thread() { return HapticScheduling::kNormal; }
int ThreadPriority::lower_threads_named(const char* /*prefix*/, int /*nice_value*/) { return 0; }

}  // namespace cathbox::session
#else
#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace cathbox::session {

void ThreadPriority::tighten_timer_slack() { (void)prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL); }

HapticScheduling ThreadPriority::favour_calling_thread() {
  tighten_timer_slack();
  sched_param param{};
  param.sched_priority = 40;  // above ordinary threads, below the kernel's own (IRQ threads at 50)
  if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0) return HapticScheduling::kRealTime;
  if (setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), -10) == 0) return HapticScheduling::kNice;
  return HapticScheduling::kNormal;
}

int ThreadPriority::lower_threads_named(const char* prefix, int nice_value) {
  int changed = 0;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task", ec)) {
    std::ifstream comm(entry.path() / "comm");
    std::string name;
    std::getline(comm, name);
    if (name.compare(0, std::strlen(prefix), prefix) != 0) continue;
    const auto tid = static_cast<id_t>(std::stoul(entry.path().filename().string()));
    if (setpriority(PRIO_PROCESS, tid, nice_value) == 0) ++changed;
  }
  return changed;
}

}  // namespace cathbox::session
#endif

namespace cathbox::session {

const char* ThreadPriority::name(HapticScheduling s) {
  switch (s) {
    case HapticScheduling::kRealTime: return "real-time (SCHED_FIFO)";
    case HapticScheduling::kNice: return "raised (nice -10)";
    case HapticScheduling::kNormal: break;
  }
  return "normal";
}

}  // namespace cathbox::session
