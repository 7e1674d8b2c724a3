#pragma once
// Things the server derives from stored content and may throw away: a case version's browser
// mesh, a result's debrief trace. Each is a pure function of content the store keeps under a
// hash (a case bundle's, a record's SHA-256), so the key names the content, never a row, and an
// entry never goes stale. In memory, bounded by bytes (the least recently used leave first);
// with a folder, also on disk (zstd, one file a key) so a restarted server does not build them
// again (a 30-minute record's trace is a two-minute replay). Thread-safe; a value is built
// outside the lock (two threads may build the same one once). A value built while any key was
// erased is answered but not kept: a deleted trainee's trace, built from their record read just
// before the delete, never lands in the cache after it.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <utility>

#include "server/result.hpp"

namespace cathbox::server {

// A trace is a pure function of the record's bytes: cached under their hash.
[[nodiscard]] inline std::string trace_cache_key(const std::string& record_hash) { return "trace2:" + record_hash; }
// The name of the file a key's value is kept in, in the cache's folder ("trace2-HASH.zst").
[[nodiscard]] std::string cache_file_name(const std::string& key);

class ArtifactCache {
 public:
  explicit ArtifactCache(std::size_t max_bytes = 256 * 1024 * 1024) : max_bytes_(max_bytes) {}

  // Keeps values in `folder` too (created when first written); empty: in memory only.
  void keep_on_disk(std::string folder) { folder_ = std::move(folder); }

  // The cached value for `key` (memory, then disk), else build() (kept when it succeeds).
  // `hit` says whether it was cached. Keys: letters, digits, '-', '_', '.', ':'.
  [[nodiscard]] Result<std::shared_ptr<const std::string>> get_or_build(const std::string& key,
                                                                       const std::function<Result<std::string>()>& build,
                                                                       bool* hit = nullptr);
  // Keeps a value built elsewhere (a trace made by the replay that checked an upload), unless a
  // key was erased since `erasures_before` (erasures() read before its source was stored).
  void put(const std::string& key, std::string value, std::uint64_t erasures_before);

  // Forgets `key`, in memory and on disk (a deleted trainee's traces, a record gone by retention).
  void erase(const std::string& key);
  // How many erase() calls so far.
  [[nodiscard]] std::uint64_t erasures() const;

  [[nodiscard]] std::size_t bytes() const;

 private:
  using Entry = std::pair<std::string, std::shared_ptr<const std::string>>;
  [[nodiscard]] std::shared_ptr<const std::string> find(const std::string& key);
  void remember(const std::string& key, const std::shared_ptr<const std::string>& value);
  [[nodiscard]] std::string file_of(const std::string& key) const;

  mutable std::mutex mutex_;
  std::size_t max_bytes_;
  std::size_t bytes_ = 0;
  std::uint64_t erasures_ = 0;
  std::string folder_;
  std::list<Entry> lru_;
  std::unordered_map<std::string, std::list<Entry>::iterator> index_;
};

}  // namespace cathbox::server
