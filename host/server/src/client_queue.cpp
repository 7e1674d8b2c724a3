#include "server/client_queue.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "server/sha256.hpp"

namespace cathbox::server {

namespace fs = std::filesystem;

namespace {

Status write_durably(const fs::path& path, const std::string& bytes) {
  const fs::path tmp = path.parent_path() / (".tmp-" + path.filename().string());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return make_error(500, tmp.string() + ": " + std::strerror(errno));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      return make_error(500, tmp.string() + ": " + why);
    }
    done += static_cast<std::size_t>(n);
  }
  const bool synced = ::fsync(fd) == 0;
  ::close(fd);
  if (!synced) return make_error(500, tmp.string() + ": fsync failed");
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) return make_error(500, path.string() + ": " + ec.message());
  const int dir = ::open(path.parent_path().c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    (void)::fsync(dir);
    ::close(dir);
  }
  return Ok{};
}

std::optional<std::string> read_all(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

Result<std::string> UploadQueue::enqueue_bytes(const std::string& bytes, std::optional<std::int64_t> assignment_id) {
  const fs::path pending = fs::path(folder_) / "pending";
  std::error_code ec;
  fs::create_directories(pending, ec);
  if (ec) return make_error(500, pending.string() + ": " + ec.message());
  const std::string hash = sha256_hex(bytes);
  nlohmann::json meta = {{"assignment", assignment_id ? nlohmann::json(*assignment_id) : nlohmann::json(nullptr)}};
  // The sidecar first: a record file present always has its assignment beside it.
  if (Status s = write_durably(pending / (hash + ".json"), meta.dump()); !s) return s.error();
  if (!fs::exists(pending / (hash + ".cbxrec"))) {
    if (Status s = write_durably(pending / (hash + ".cbxrec"), bytes); !s) return s.error();
  }
  return hash;
}

Result<std::string> UploadQueue::enqueue_file(const std::string& path, std::optional<std::int64_t> assignment_id) {
  const std::optional<std::string> bytes = read_all(path);
  if (!bytes) return make_error(400, path + ": cannot read");
  return enqueue_bytes(*bytes, assignment_id);
}

std::vector<QueuedRecord> UploadQueue::pending() const {
  std::vector<std::pair<fs::file_time_type, QueuedRecord>> found;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(fs::path(folder_) / "pending", ec)) {
    const fs::path p = entry.path();
    if (p.extension() != ".cbxrec" || p.filename().string().rfind(".tmp-", 0) == 0) continue;
    QueuedRecord r;
    r.hash = p.stem().string();
    r.path = p.string();
    if (const std::optional<std::string> meta = read_all(fs::path(p).replace_extension(".json"))) {
      try {
        const nlohmann::json j = nlohmann::json::parse(*meta);
        if (j.at("assignment").is_number_integer()) r.assignment_id = j.at("assignment").get<std::int64_t>();
      } catch (const std::exception&) {
      }
    }
    std::error_code time_ec;
    found.emplace_back(fs::last_write_time(p, time_ec), std::move(r));
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first || (a.first == b.first && a.second.hash < b.second.hash); });
  std::vector<QueuedRecord> out;
  for (auto& [t, r] : found) out.push_back(std::move(r));
  return out;
}

std::vector<std::string> UploadQueue::refused() const {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(fs::path(folder_) / "refused", ec)) {
    if (entry.path().extension() == ".cbxrec") out.push_back(entry.path().stem().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

FlushReport UploadQueue::flush(ServerClient& client) {
  FlushReport report;
  const std::vector<QueuedRecord> queue = pending();
  std::size_t i = 0;
  for (; i < queue.size(); ++i) {
    const QueuedRecord& r = queue[i];
    const std::optional<std::string> bytes = read_all(r.path);
    if (!bytes) continue;  // removed meanwhile
    const UploadOutcome outcome = client.upload_record(*bytes, r.assignment_id);
    std::error_code ec;
    if (outcome.verdict == UploadVerdict::kStored || outcome.verdict == UploadVerdict::kDuplicate) {
      (outcome.verdict == UploadVerdict::kStored ? report.stored : report.duplicates)++;
      fs::remove(r.path, ec);
      fs::remove(fs::path(r.path).replace_extension(".json"), ec);
    } else if (outcome.verdict == UploadVerdict::kRefused) {
      ++report.refused;
      const fs::path refused = fs::path(folder_) / "refused";
      fs::create_directories(refused, ec);
      (void)write_durably(refused / (r.hash + ".txt"), outcome.message + "\n");
      fs::rename(r.path, refused / (r.hash + ".cbxrec"), ec);
      fs::remove(fs::path(r.path).replace_extension(".json"), ec);
    } else {
      report.stopped_by = outcome.message.empty() ? "server unavailable" : outcome.message;
      break;
    }
  }
  report.left = static_cast<int>(pending().size());
  return report;
}

Status write_file_durably(const std::string& path, const std::string& bytes) {
  std::error_code ec;
  fs::create_directories(fs::path(path).parent_path(), ec);
  if (ec) return make_error(500, fs::path(path).parent_path().string() + ": " + ec.message());
  return write_durably(path, bytes);
}

}  // namespace cathbox::server
