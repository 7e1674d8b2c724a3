// LiveStream: one rig's WebSocket on its own thread. push() only swaps the pending frame under
// a mutex; the thread sends the newest and reconnects after failures.
#include <condition_variable>
#include <mutex>
#include <thread>

#include "server/client.hpp"

namespace cathbox::server {

struct LiveStream::Impl {
  Options options;
  mutable std::mutex mutex;
  std::condition_variable wake;
  std::optional<std::string> pending;
  bool stopping = false;
  bool is_connected = false;
  LiveStreamStats stats;
  std::thread thread;

  std::string target() const {
    std::string t = "/api/v1/live/rigs/" + options.rig + "/stream?case=" + options.case_name;
    if (options.case_version > 0) t += "&version=" + std::to_string(options.case_version);
    if (options.assignment_id) t += "&assignment=" + std::to_string(*options.assignment_id);
    return t;
  }

  void run() {
    for (;;) {
      {
        std::lock_guard lock(mutex);
        if (stopping) return;
      }
      WsClient ws(10000);
      const Status connected = ws.connect(options.base_url, target(), options.token);
      {
        std::lock_guard lock(mutex);
        is_connected = connected.ok();
        if (connected) {
          ++stats.connects;
        } else {
          stats.last_error = connected.error().message;
        }
      }
      if (connected) {
        for (;;) {
          std::string frame;
          bool stop = false;
          {
            std::unique_lock lock(mutex);
            wake.wait(lock, [&] { return stopping || pending.has_value(); });
            stop = stopping;
            if (pending) {
              frame = std::move(*pending);
              pending.reset();
            }
          }
          if (!frame.empty()) {
            const Status sent = ws.send(frame);
            std::lock_guard lock(mutex);
            if (!sent) {
              stats.last_error = sent.error().message;
              is_connected = false;
              break;
            }
            ++stats.sent;
          }
          if (stop) {
            (void)ws.send(R"({"type":"end"})");
            ws.close();
            std::lock_guard lock(mutex);
            is_connected = false;
            return;
          }
        }
      }
      std::unique_lock lock(mutex);
      wake.wait_for(lock, std::chrono::milliseconds(options.reconnect_ms), [&] { return stopping; });
    }
  }
};

LiveStream::LiveStream(Options options) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
  impl_->thread = std::thread([impl = impl_.get()] { impl->run(); });
}

LiveStream::~LiveStream() {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->stopping = true;
  }
  impl_->wake.notify_all();
  if (impl_->thread.joinable()) impl_->thread.join();
}

void LiveStream::push(std::string frame_json) {
  {
    std::lock_guard lock(impl_->mutex);
    ++impl_->stats.pushed;
    if (impl_->pending) ++impl_->stats.replaced;
    impl_->pending = std::move(frame_json);
  }
  impl_->wake.notify_one();
}

LiveStreamStats LiveStream::stats() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->stats;
}

bool LiveStream::connected() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->is_connected;
}

}  // namespace cathbox::server
