#pragma once
// The page's fluoroscopic image made off the haptic tick: a thread of its own (an Emscripten
// pthread, in the browser a Web Worker of the module's pool) runs BrowserFluoro::frame on a copy
// of the snapshot the haptic worker hands it, so that the image's CPU work (the inputs from the
// snapshot, a pulse's tool tubes, a new pose's phantom: up to tens of ms) never delays a tick.
// The haptic side never waits for it: request() and take() only try the lock (a frame it cannot
// hand over or take now is handed or taken at the next frame). Three images rotate: the thread's
// own (staged), the newest made (ready) and the one the page is sent (shown, whose data the
// worker copies out); each image's phantom and scenes are copied only when their versions change.
// The session is untouched (the image reads a copy of a snapshot): the record is the same.
#include <condition_variable>
#include <memory>
#include <mutex>

#include "base/jthread.hpp"
#include "session/scene_snapshot.hpp"
#include "wasm/browser_fluoro.hpp"

namespace cathbox::wasm {

class FluoroThread {
 public:
  // `opened`: the session's BrowserFluoro after open() (its lumen and cells), copied.
  explicit FluoroThread(const BrowserFluoro& opened);
  ~FluoroThread();
  FluoroThread(const FluoroThread&) = delete;
  FluoroThread& operator=(const FluoroThread&) = delete;

  // The image for width x height from `snapshot` (copied), unless the thread holds the lock now.
  void request(const session::SceneSnapshot& snapshot, int width, int height);
  // The newest image made, swapped in if the lock is free now; null until one is made.
  const FluoroImage* take();
  [[nodiscard]] const FluoroImage& shown() const { return shown_; }

 private:
  void run(const base::stop_token& stop);
  static void stage(const FluoroImage& from, FluoroImage& to);

  BrowserFluoro fluoro_;  // the thread's alone
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::unique_ptr<session::SceneSnapshot> pending_ = std::make_unique<session::SceneSnapshot>();
  std::unique_ptr<session::SceneSnapshot> working_ = std::make_unique<session::SceneSnapshot>();
  bool has_pending_ = false;
  int width_ = 0;
  int height_ = 0;
  FluoroImage staged_;
  FluoroImage ready_;
  FluoroImage shown_;
  long made_ = 0;   // images made (ready_ holds the newest)
  long taken_ = 0;  // the one in shown_
  base::jthread thread_;  // last: started once the members exist, joined first
};

}  // namespace cathbox::wasm
