#include "server/live_hub.hpp"

#include <algorithm>

namespace cathbox::server {

void LiveHub::subscribe(const std::string& rig, const std::shared_ptr<LiveSubscriber>& subscriber) {
  std::lock_guard lock(mutex_);
  std::vector<Weak>& list = rigs_[rig];
  for (const Weak& w : list) {
    if (w.lock() == subscriber) return;
  }
  list.push_back(subscriber);
}

void LiveHub::unsubscribe(const std::string& rig, const LiveSubscriber* subscriber) {
  std::lock_guard lock(mutex_);
  const auto it = rigs_.find(rig);
  if (it == rigs_.end()) return;
  std::erase_if(it->second, [&](const Weak& w) {
    const auto s = w.lock();
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
  const auto gone = [&](const Weak& w) {
    const auto s = w.lock();
    return !s || s.get() == subscriber;
  };
  for (auto it = rigs_.begin(); it != rigs_.end();) {
    std::erase_if(it->second, gone);
    it = it->second.empty() ? rigs_.erase(it) : std::next(it);
  }
  std::erase_if(events_, gone);
}

void LiveHub::send_to(std::vector<Weak>& list, const LiveMessage& message) {
  bool dead = false;
  for (const Weak& w : list) {
    if (const auto s = w.lock()) {
      s->deliver(message);
    } else {
      dead = true;
    }
  }
  if (dead) std::erase_if(list, [](const Weak& w) { return w.expired(); });
}

void LiveHub::deliver_frame(const std::string& rig, const LiveMessage& message) {
  std::lock_guard lock(mutex_);
  const auto it = rigs_.find(rig);
  if (it != rigs_.end()) send_to(it->second, message);
}

void LiveHub::deliver_event(const LiveMessage& message) {
  std::lock_guard lock(mutex_);
  send_to(events_, message);
}

std::size_t LiveHub::subscriptions() const {
  std::lock_guard lock(mutex_);
  std::size_t n = events_.size();
  for (const auto& [rig, list] : rigs_) n += list.size();
  return n;
}

}  // namespace cathbox::server
