#pragma once
// In-process fan-out of live messages: each rig's frames go to the subscribers watching that
// rig; rig events (started, ended) go to every event subscriber. Subscribers are held weakly
// (a closed WebSocket just disappears) and must not block in deliver(): the WebSocket session
// posts the message to its own strand and keeps a bounded queue.
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace cathbox::server {

using LiveMessage = std::shared_ptr<const std::string>;

class LiveSubscriber {
 public:
  virtual ~LiveSubscriber() = default;
  virtual void deliver(const LiveMessage& message) = 0;
};

class LiveHub {
 public:
  // `only_user`: a trainee's watch, good only while that user streams the rig. Rights are
  // checked again on the rig's events: when another user's stream starts on it, or its stream
  // ends, such subscriptions end (the subscriber is told: {"type":"unwatched","rig",...}).
  void subscribe(const std::string& rig, const std::shared_ptr<LiveSubscriber>& subscriber, const std::string& only_user = {});
  void unsubscribe(const std::string& rig, const LiveSubscriber* subscriber);
  void subscribe_events(const std::shared_ptr<LiveSubscriber>& subscriber);
  void unsubscribe_all(const LiveSubscriber* subscriber);

  // Frames of `rig` to its local subscribers; events to local event subscribers.
  void deliver_frame(const std::string& rig, const LiveMessage& message);
  // Also applies a started or ended event to the restricted subscriptions of its rig.
  void deliver_event(const LiveMessage& message);

  [[nodiscard]] std::size_t subscriptions() const;

 private:
  using Weak = std::weak_ptr<LiveSubscriber>;
  struct Subscription {
    Weak subscriber;
    std::string only_user;  // empty: any stream of the rig
  };
  template <class List>
  static void send_to(List& list, const LiveMessage& message);
  // Ends the restricted subscriptions of `rig` not of `streaming_user` (empty: all of them).
  void recheck(const std::string& rig, const std::string& streaming_user);
  mutable std::mutex mutex_;
  std::map<std::string, std::vector<Subscription>> rigs_;
  std::vector<Weak> events_;
};

// Carries messages to every server instance's hub: LocalLiveBus for one instance (SQLite),
// PgLiveBus through PostgreSQL LISTEN/NOTIFY for several instances on one database.
class LiveBus {
 public:
  virtual ~LiveBus() = default;
  virtual void publish_frame(const std::string& rig, const LiveMessage& message) = 0;
  virtual void publish_event(const LiveMessage& message) = 0;
};

class LocalLiveBus final : public LiveBus {
 public:
  explicit LocalLiveBus(LiveHub& hub) : hub_(hub) {}
  void publish_frame(const std::string& rig, const LiveMessage& message) override { hub_.deliver_frame(rig, message); }
  void publish_event(const LiveMessage& message) override { hub_.deliver_event(message); }

 private:
  LiveHub& hub_;
};

}  // namespace cathbox::server
