#pragma once
// A bounded pool of database connections shared by the SQLite and PostgreSQL backends: take
// an idle one, open a new one while under the limit, else wait for one to come back.
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "server/sql.hpp"

namespace cathbox::server {

template <class Connection>
class ConnectionPool {
 public:
  using Opener = std::function<std::unique_ptr<Connection>()>;
  ConnectionPool(int max_connections, Opener open) : max_(max_connections < 1 ? 1 : max_connections), open_(std::move(open)) {}

  // Opens one connection now (to fail early); throws what the opener throws.
  void open_first() {
    auto c = open_();
    std::lock_guard lock(mutex_);
    idle_.push_back(std::move(c));
    ++count_;
  }

  std::unique_ptr<Connection> acquire() {
    std::unique_lock lock(mutex_);
    for (;;) {
      if (!idle_.empty()) {
        auto c = std::move(idle_.back());
        idle_.pop_back();
        return c;
      }
      if (count_ < max_) {
        ++count_;
        lock.unlock();
        try {
          return open_();
        } catch (...) {
          lock.lock();
          --count_;
          throw;
        }
      }
      ++waiting_;
      available_.wait(lock);
      --waiting_;
    }
  }

  void release(std::unique_ptr<Connection> c) {
    {
      std::lock_guard lock(mutex_);
      idle_.push_back(std::move(c));
    }
    available_.notify_one();
  }

  [[nodiscard]] PoolStats stats() const {
    std::lock_guard lock(mutex_);
    return PoolStats{count_, static_cast<int>(idle_.size()), max_, waiting_};
  }

  // The connection in hand broke (the caller destroys it): forget it and the idle ones, which
  // almost certainly broke with it.
  void discard() {
    std::vector<std::unique_ptr<Connection>> stale;
    {
      std::lock_guard lock(mutex_);
      count_ -= 1 + static_cast<int>(idle_.size());
      stale.swap(idle_);
    }
    available_.notify_all();
  }

 private:
  const int max_;
  Opener open_;
  mutable std::mutex mutex_;
  std::condition_variable available_;
  std::vector<std::unique_ptr<Connection>> idle_;
  int count_ = 0;
  int waiting_ = 0;
};

}  // namespace cathbox::server
