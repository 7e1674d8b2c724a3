#pragma once
// Things the server derives from stored content and may throw away: a case version's browser
// mesh, a result's debrief trace. Each is a pure function of content the store keeps under a
// hash (a case bundle's, a record's SHA-256), so the key names the content, never a row, and an
// entry never goes stale. Bounded by bytes; the least recently used entries leave first.
// Thread-safe; a value is built outside the lock (two threads may build the same one once).
#include <cstddef>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <utility>

#include "server/result.hpp"

namespace cathbox::server {

class ArtifactCache {
 public:
  explicit ArtifactCache(std::size_t max_bytes = 256 * 1024 * 1024) : max_bytes_(max_bytes) {}

  // The cached value for `key`, else build() (stored when it succeeds). `hit` says which.
  [[nodiscard]] Result<std::shared_ptr<const std::string>> get_or_build(const std::string& key,
                                                                       const std::function<Result<std::string>()>& build,
                                                                       bool* hit = nullptr) {
    {
      std::lock_guard lock(mutex_);
      const auto it = index_.find(key);
      if (it != index_.end()) {
        lru_.splice(lru_.begin(), lru_, it->second);
        if (hit != nullptr) *hit = true;
        return it->second->second;
      }
    }
    if (hit != nullptr) *hit = false;
    Result<std::string> built = build();
    if (!built) return built.error();
    auto value = std::make_shared<const std::string>(std::move(built.value()));
    std::lock_guard lock(mutex_);
    if (index_.count(key) == 0 && value->size() <= max_bytes_) {
      lru_.emplace_front(key, value);
      index_[key] = lru_.begin();
      bytes_ += value->size();
      while (bytes_ > max_bytes_) {
        bytes_ -= lru_.back().second->size();
        index_.erase(lru_.back().first);
        lru_.pop_back();
      }
    }
    return value;
  }

  // Stores a value built elsewhere (a trace made by the replay that checked an upload).
  void put(const std::string& key, std::string value) {
    (void)get_or_build(key, [&]() -> Result<std::string> { return std::move(value); });
  }

  [[nodiscard]] std::size_t bytes() const {
    std::lock_guard lock(mutex_);
    return bytes_;
  }

 private:
  using Entry = std::pair<std::string, std::shared_ptr<const std::string>>;
  mutable std::mutex mutex_;
  std::size_t max_bytes_;
  std::size_t bytes_ = 0;
  std::list<Entry> lru_;
  std::unordered_map<std::string, std::list<Entry>::iterator> index_;
};

}  // namespace cathbox::server
