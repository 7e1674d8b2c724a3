#pragma once
// The trainer's link to cathbox-server (host/server's client library): log in, list the
// trainee's assignments and download their cases, stream the live run (~30 frames per second
// of simulated time), and hand every finished record to the on-disk upload queue, which a
// worker thread flushes to the server. Nothing here blocks the render loop for a network
// round trip except open() and, headless, flush_now().
//
// Without a server, or when it is unreachable, the trainer works as before: open() answers a
// link that is offline, the assignments come from the last list this rig saw (cached beside
// the downloaded cases), and records wait in the queue until a later flush reaches the server
// (the queue and the server are both idempotent by the record's content hash: none lost, none
// duplicated).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "server/client_queue.hpp"
#include "session/scene_snapshot.hpp"

namespace cathbox::app {

struct ServerLinkOptions {
  std::string url;        // https://HOST:PORT (or http:// on loopback)
  std::string ca_file;    // the CA that signed the server's certificate; "": the system trust store
  std::string user;
  std::string password;
  std::string rig;        // the name instructors see; default: the host name
  std::string cache_dir;  // downloaded cases and the last assignment list (default: default_server_cache_dir())
  std::string queue_dir;  // the upload queue (default: $XDG_DATA_HOME/cathbox/upload-queue)
  int timeout_ms = 10'000;
};

struct AssignedCase {
  server::AssignmentInfo info;  // id, case name and version (0: the newest), note, due date
  std::string case_path;        // the downloaded case file ("" when it could not be downloaded)
};

class ServerLink {
 public:
  // Logs in and fetches the assignments and their cases. Never fails: when the server cannot
  // be reached the link is offline and `note` says why.
  [[nodiscard]] static std::unique_ptr<ServerLink> open(const ServerLinkOptions& options, std::string& note);
  ~ServerLink();  // ends a stream, finishes the flush in progress (bounded by the timeout)
  ServerLink(const ServerLink&) = delete;
  ServerLink& operator=(const ServerLink&) = delete;

  [[nodiscard]] bool online() const;
  [[nodiscard]] const ServerLinkOptions& options() const { return options_; }
  [[nodiscard]] const std::vector<AssignedCase>& assigned() const { return assigned_; }
  // The assignment whose case is at `case_path`, if any.
  [[nodiscard]] std::optional<std::int64_t> assignment_for(const std::string& case_path) const;

  // A run starts: the live stream opens (when online) for this case and these tools.
  void begin_run(const std::string& case_name, std::optional<std::int64_t> assignment_id,
                 std::vector<std::string> tool_names);
  // Waits up to timeout_ms for the stream to be connected (headless runs in virtual time wait,
  // so that instructors see them at all); answers whether it is.
  bool wait_streaming(int timeout_ms);
  // The newest state; sent when 1/30 s of simulated time passed since the last frame.
  void publish(const session::SceneSnapshot& snap);
  // The run ended and its record (if any) is closed: the stream ends, the record is queued
  // durably and (background) a flush starts on the link's worker thread. Answers why the record
  // could not be queued ("" when it was, or when there is none).
  [[nodiscard]] std::string end_run(const std::string& record_path, std::optional<std::int64_t> assignment_id, bool background = true);
  // Uploads what is queued now, on the calling thread (stopped_by: why records are left).
  server::FlushReport flush_now();
  // One line for the panel: "server http://...: online as ann, 2 assignments, 0 queued".
  [[nodiscard]] std::string status_line() const;

  // The frame a run sends (live_schema.hpp in host/server).
  [[nodiscard]] static std::string frame_json(const session::SceneSnapshot& snap, std::uint64_t seq,
                                              const std::vector<std::string>& tool_names);

  struct Impl;

 private:
  explicit ServerLink(ServerLinkOptions options);
  ServerLinkOptions options_;
  std::vector<AssignedCase> assigned_;
  std::unique_ptr<Impl> impl_;
};

// Where the trainer keeps downloaded cases: $XDG_CACHE_HOME/cathbox/server (or ~/.cache/...).
[[nodiscard]] std::string default_server_cache_dir();

}  // namespace cathbox::app
