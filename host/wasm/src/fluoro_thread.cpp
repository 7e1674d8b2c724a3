#include "wasm/fluoro_thread.hpp"

#include <utility>

namespace cathbox::wasm {

FluoroThread::FluoroThread(const BrowserFluoro& opened)
    : fluoro_(opened), thread_([this](const base::stop_token& stop) { run(stop); }) {}

FluoroThread::~FluoroThread() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  thread_.request_stop();
  thread_.join();
}

void FluoroThread::request(const session::SceneSnapshot& snapshot, int width, int height) {
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  *pending_ = snapshot;
  width_ = width;
  height_ = height;
  has_pending_ = true;
  lock.unlock();
  wake_.notify_one();
}

const FluoroImage* FluoroThread::take() {
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (lock.owns_lock() && made_ > taken_) {
    std::swap(ready_, shown_);
    taken_ = made_;
  }
  return taken_ > 0 ? &shown_ : nullptr;
}

// `to` made the same as `from`, its phantom and scenes copied only when their versions differ.
void FluoroThread::stage(const FluoroImage& from, FluoroImage& to) {
  if (to.header[kPhantomVersion] != from.header[kPhantomVersion]) to.phantom = from.phantom;
  if (to.header[kSceneVersion] != from.header[kSceneVersion]) {
    to.scene_floats = from.scene_floats;
    to.scene_indices = from.scene_indices;
  }
  to.header = from.header;
}

void FluoroThread::run(const base::stop_token& stop) {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stopping_ || has_pending_; });
    if (stopping_ || stop.stop_requested()) return;
    std::swap(pending_, working_);
    has_pending_ = false;
    const int width = width_;
    const int height = height_;
    lock.unlock();
    fluoro_.frame(*working_, width, height);
    stage(fluoro_.image(), staged_);
    lock.lock();
    std::swap(staged_, ready_);
    ++made_;
  }
}

}  // namespace cathbox::wasm
