#pragma once
// Scheduling help for the haptic thread on Linux: a 1 us timer slack for the calling thread
// (its sleeps end on time); the real-time FIFO policy when the process may use it (root, or
// an rtprio limit), else a lower nice value when allowed; and, with no privilege needed, a
// lower priority for the process's software-rasteriser worker threads (Mesa's llvmpipe), which
// would otherwise take both cores in bursts while the haptic thread waits to be scheduled.
namespace cathbox::session {

enum class HapticScheduling { kNormal, kNice, kRealTime };

struct ThreadPriority {
  // Called on the haptic thread: timer slack, then the best policy the process is allowed.
  static HapticScheduling favour_calling_thread();
  static const char* name(HapticScheduling s);
  static void tighten_timer_slack();
  // Raises the nice value of this process's threads whose name starts with `prefix`; returns
  // how many were changed.
  static int lower_threads_named(const char* prefix, int nice_value);
};

}  // namespace cathbox::session
