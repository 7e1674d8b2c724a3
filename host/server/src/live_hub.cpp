#include "server/live_hub.hpp"

#include <algorithm>

#include <nlohmann/json.hpp>

namespace cathbox::server {

namespace {

std::shared_ptr<LiveSubscriber> lock_of(const std::weak_ptr<LiveSubscriber>& w) { return w.lock(); }
template <class S>
std::shared_ptr<LiveSubscriber> lock_of(const S& s) {
  return s.subscriber.lock();
}

}  // namespace

void LiveHub::subscribe(const std::string& rig, const std::shared_ptr<LiveSubscriber>& subscriber, const std::string& only_user) {
  std::lock_guard lock(mutex_);
  std::vector<Subscription>& list = rigs_[rig];
  for (Subscription& s : list) {
    if (s.subscriber.lock() == subscriber) {
      s.only_user = only_user;
      return;
    }
  }
  list.push_back({subscriber, only_user});
}

void LiveHub::unsubscribe(const std::string& rig, const LiveSubscriber* subscriber) {
  std::lock_guard lock(mutex_);
  const auto it = rigs_.find(rig);
  if (it == rigs_.end()) return;
  std::erase_if(it->second, [&](const Subscription& w) {
    const auto s = w.subscriber.lock();
    return !s || s.get() == subscriber;
  });
  if (it->second.empty()) rigs_.erase(it);
}

void LiveHub::subscribe_events(const std::shared_ptr<LiveSubscriber>& subscriber) {
  std::lock_guard lock(mutex_);
  events_.push_back(subscriber);
}

void LiveHub::unsubscribe_all(const LiveSubscriber* subscriber) {
  std::lock_guard lock(mutex_);
  for (auto it = rigs_.begin(); it != rigs_.end();) {
    std::erase_if(it->second, [&](const Subscription& w) {
      const auto s = w.subscriber.lock();
      return !s || s.get() == subscriber;
    });
    it = it->second.empty() ? rigs_.erase(it) : std::next(it);
  }
  std::erase_if(events_, [&](const Weak& w) {
    const auto s = w.lock();
    return !s || s.get() == subscriber;
  });
}

template <class List>
void LiveHub::send_to(List& list, const LiveMessage& message) {
  bool dead = false;
  for (const auto& w : list) {
    if (const auto s = lock_of(w)) {
      s->deliver(message);
    } else {
      dead = true;
    }
  }
  if (dead) std::erase_if(list, [](const auto& w) { return lock_of(w) == nullptr; });
}

void LiveHub::deliver_frame(const std::string& rig, const LiveMessage& message) {
  std::lock_guard lock(mutex_);
  const auto it = rigs_.find(rig);
  if (it != rigs_.end()) send_to(it->second, message);
}

void LiveHub::recheck(const std::string& rig, const std::string& streaming_user) {
  const auto it = rigs_.find(rig);
  if (it == rigs_.end()) return;
  const auto notice = std::make_shared<const std::string>(
      nlohmann::json{{"type", "unwatched"}, {"rig", rig}, {"why", "the rig's stream changed: watch it again while you stream it"}}.dump());
  std::erase_if(it->second, [&](const Subscription& w) {
    if (w.only_user.empty() || (!streaming_user.empty() && w.only_user == streaming_user)) return false;
    if (const auto s = w.subscriber.lock()) s->deliver(notice);
    return true;
  });
  if (it->second.empty()) rigs_.erase(it);
}

void LiveHub::deliver_event(const LiveMessage& message) {
  std::lock_guard lock(mutex_);
  // Events are rare (a stream's start and end): parsed here to check trainees' watches again.
  const nlohmann::json e = nlohmann::json::parse(*message, nullptr, false);
  if (e.is_object() && e.contains("rig")) {
    const std::string type = e.value("type", "");
    if (type == "started" && e["rig"].is_object()) recheck(e["rig"].value("rig", ""), e["rig"].value("user", ""));
    if (type == "ended" && e["rig"].is_string()) recheck(e["rig"].get<std::string>(), "");
  }
  send_to(events_, message);
}

std::size_t LiveHub::subscriptions() const {
  std::lock_guard lock(mutex_);
  std::size_t n = events_.size();
  for (const auto& [rig, list] : rigs_) n += list.size();
  return n;
}

}  // namespace cathbox::server
