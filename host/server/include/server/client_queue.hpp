#pragma once
// Finished session records waiting for the server, on disk, so none is lost and none is
// duplicated whatever happens to the trainer, the network or the server:
//
//   FOLDER/pending/<sha256>.cbxrec   the record's bytes (written to a temporary name, fsynced,
//   FOLDER/pending/<sha256>.json     then renamed; the .json beside it holds the assignment)
//   FOLDER/refused/<sha256>.cbxrec   records the server will never take, with .txt saying why
//
// A record is named by its content hash, so queueing it twice keeps one copy; the server is
// idempotent by the same hash, so an upload acknowledged but not yet removed here (the trainer
// died in between) is answered "duplicate" next time and then removed. flush() uploads in the
// order queued and stops at the first failure that may pass (unreachable, 5xx, 401).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "server/client.hpp"
#include "server/result.hpp"

namespace cathbox::server {

struct QueuedRecord {
  std::string hash;
  std::string path;
  std::optional<std::int64_t> assignment_id;
};

struct FlushReport {
  int stored = 0;
  int duplicates = 0;
  int refused = 0;
  int left = 0;            // still pending
  std::string stopped_by;  // why the flush stopped early ("" when the queue emptied)
};

class UploadQueue {
 public:
  explicit UploadQueue(std::string folder) : folder_(std::move(folder)) {}
  // Copies the record into the queue (durably) and answers its hash.
  [[nodiscard]] Result<std::string> enqueue_bytes(const std::string& bytes, std::optional<std::int64_t> assignment_id);
  [[nodiscard]] Result<std::string> enqueue_file(const std::string& path, std::optional<std::int64_t> assignment_id);
  [[nodiscard]] std::vector<QueuedRecord> pending() const;
  [[nodiscard]] std::vector<std::string> refused() const;
  [[nodiscard]] FlushReport flush(ServerClient& client);
  [[nodiscard]] const std::string& folder() const { return folder_; }

 private:
  std::string folder_;
};

// Writes `bytes` to `path` durably: a temporary file in the same folder, fsync, rename, fsync of
// the folder (which is created when missing).
[[nodiscard]] Status write_file_durably(const std::string& path, const std::string& bytes);

}  // namespace cathbox::server
