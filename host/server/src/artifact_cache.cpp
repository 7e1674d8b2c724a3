#include "server/artifact_cache.hpp"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <system_error>

#include "server/sha256.hpp"
#include "server/zstd_codec.hpp"

namespace cathbox::server {

namespace {

constexpr std::size_t kMaxValueBytes = 512 * 1024 * 1024;  // refuse to inflate anything larger from disk

}  // namespace

std::string cache_file_name(const std::string& key) {
  std::string name = key;
  for (char& c : name) {
    if (c == ':') c = '-';
  }
  return name + ".zst";
}

std::string ArtifactCache::file_of(const std::string& key) const {
  return (std::filesystem::path(folder_) / cache_file_name(key)).string();
}

std::shared_ptr<const std::string> ArtifactCache::find(const std::string& key) {
  {
    std::lock_guard lock(mutex_);
    const auto it = index_.find(key);
    if (it != index_.end()) {
      lru_.splice(lru_.begin(), lru_, it->second);
      return it->second->second;
    }
  }
  if (folder_.empty()) return nullptr;
  std::ifstream in(file_of(key), std::ios::binary);
  if (!in) return nullptr;
  const std::string frame{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  Result<std::string> plain = zstd_decompress(frame, kMaxValueBytes);
  if (!plain) return nullptr;  // a damaged file is built again (and rewritten)
  auto value = std::make_shared<const std::string>(std::move(plain.value()));
  remember(key, value);
  return value;
}

void ArtifactCache::remember(const std::string& key, const std::shared_ptr<const std::string>& value) {
  std::lock_guard lock(mutex_);
  if (index_.count(key) != 0 || value->size() > max_bytes_) return;
  lru_.emplace_front(key, value);
  index_[key] = lru_.begin();
  bytes_ += value->size();
  while (bytes_ > max_bytes_) {
    bytes_ -= lru_.back().second->size();
    index_.erase(lru_.back().first);
    lru_.pop_back();
  }
}

Result<std::shared_ptr<const std::string>> ArtifactCache::get_or_build(const std::string& key,
                                                                      const std::function<Result<std::string>()>& build, bool* hit) {
  if (std::shared_ptr<const std::string> found = find(key)) {
    if (hit != nullptr) *hit = true;
    return found;
  }
  if (hit != nullptr) *hit = false;
  const std::uint64_t erasures_before = erasures();
  Result<std::string> built = build();
  if (!built) return built.error();
  auto value = std::make_shared<const std::string>(std::move(built.value()));
  if (erasures() != erasures_before) return value;  // its source may be what was erased
  remember(key, value);
  if (!folder_.empty()) {
    // Written aside and renamed: a reader never sees half a file. A failure only costs a rebuild.
    std::error_code ec;
    std::filesystem::create_directories(folder_, ec);
    const std::string path = file_of(key);
    const std::string aside = path + "." + random_token(6) + ".tmp";
    {
      std::ofstream out(aside, std::ios::binary | std::ios::trunc);
      out << zstd_compress(*value, 3);
    }
    std::filesystem::rename(aside, path, ec);
    if (ec) std::filesystem::remove(aside, ec);
  }
  return value;
}

void ArtifactCache::put(const std::string& key, std::string value, std::uint64_t erasures_before) {
  if (erasures() != erasures_before) return;
  (void)get_or_build(key, [&]() -> Result<std::string> { return std::move(value); });
}

std::uint64_t ArtifactCache::erasures() const {
  std::lock_guard lock(mutex_);
  return erasures_;
}

void ArtifactCache::erase(const std::string& key) {
  std::lock_guard lock(mutex_);
  ++erasures_;
  if (const auto it = index_.find(key); it != index_.end()) {
    bytes_ -= it->second->second->size();
    lru_.erase(it->second);
    index_.erase(it);
  }
  if (!folder_.empty()) {
    std::error_code ignored;
    std::filesystem::remove(file_of(key), ignored);
  }
}

std::size_t ArtifactCache::bytes() const {
  std::lock_guard lock(mutex_);
  return bytes_;
}

}  // namespace cathbox::server
