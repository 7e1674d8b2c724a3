#pragma once
// Live messages between server instances through PostgreSQL's LISTEN/NOTIFY, so a rig that
// streams to instance A is watched from instance B. No broker of our own: each instance
// LISTENs on channel `cathbox_live` on a dedicated connection and NOTIFYs what its own rigs
// send (batched: one statement per batch, `pg_notify` over a JSON array parameter).
//
// Payload: "<instance>\t<F|E>\t<rig>\t<message>", where message is the watcher-ready JSON,
// or "@<id>" when it is over NOTIFY's 8000-byte limit: the text then waits in the unlogged
// table live_overflow (purged after a minute). Each instance skips its own notifications (its
// local watchers got the message directly).
//
// Live frames are not durable: while the database is unreachable, frames for other
// instances are dropped (counted) and both threads reconnect with backoff.
#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "server/clock.hpp"
#include "server/live_hub.hpp"
#include "server/result.hpp"
#include "server/store.hpp"

namespace cathbox::server {

struct PgLiveBusStats {
  std::uint64_t sent = 0;
  std::uint64_t received = 0;
  std::uint64_t dropped = 0;
  std::uint64_t overflowed = 0;
  std::uint64_t reconnects = 0;
};

class PgLiveBus final : public LiveBus {
 public:
  // Connects the listener (fails at start-up with a clear line rather than later).
  [[nodiscard]] static Result<std::unique_ptr<PgLiveBus>> start(const std::string& url, LiveHub& hub, Store& store, Clock& clock,
                                                                std::string instance_id);
  ~PgLiveBus() override;
  PgLiveBus(const PgLiveBus&) = delete;
  PgLiveBus& operator=(const PgLiveBus&) = delete;

  void publish_frame(const std::string& rig, const LiveMessage& message) override;
  void publish_event(const LiveMessage& message) override;
  [[nodiscard]] PgLiveBusStats stats() const;
  // Blocks until the listener is connected and listening (tests use it after a restart).
  [[nodiscard]] bool wait_listening(int timeout_ms);

  static constexpr std::size_t kMaxNotifyPayload = 7900;
  static constexpr std::size_t kMaxQueued = 8192;

 private:
  struct Impl;
  PgLiveBus(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace cathbox::server
