#pragma once
// Live sessions: who may stream on which rig, who may watch it, and the messages that flow.
// No sockets here: the HTTP/WebSocket layer calls these and writes what they return.
//
//  - A rig streams as the logged-in user: start() claims the rig name in the store (refused
//    with 409 while another user streams on it, for the stream's whole life however silent:
//    this instance refuses from its open streams, and keep_claims() refreshes their store
//    claims so other instances, which go by the claim's age, refuse too), announces
//    "started" to supervisors, and frame() validates each frame, stamps it and publishes it on
//    the bus. Frames beyond max_frames_per_s are dropped (counted), not refused.
//  - Instructors and admins may watch any rig; a trainee only a rig they stream themselves.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/auth.hpp"
#include "server/clock.hpp"
#include "server/live_hub.hpp"
#include "server/result.hpp"
#include "server/store.hpp"

namespace cathbox::server {

struct LiveOptions {
  std::int64_t touch_every_us = 2'000'000;  // refresh the rig's last_seen this often
  std::int64_t stale_after_us = 10'000'000; // a rig not seen for this long is gone
  double max_frames_per_s = 60.0;
};

// One streaming rig, owned by its WebSocket session.
struct Publisher {
  Caller caller;
  LiveRig rig;
  std::int64_t last_touch_us = 0;
  double frame_tokens = 0.0;
  std::int64_t tokens_at_us = 0;
  std::uint64_t frames = 0;
  std::uint64_t dropped = 0;
  bool ended = false;
  std::uint64_t stream_id = 0;  // this instance's open stream of the rig (LiveService)
};

class LiveService {
 public:
  LiveService(Store& store, Clock& clock, LiveBus& bus, std::string instance, LiveOptions options = {});

  [[nodiscard]] const std::string& instance() const { return instance_; }
  [[nodiscard]] const LiveOptions& options() const { return options_; }

  // The stream's opening: rig from the URL, query parameters case, version, assignment. Uses
  // the store (call off the I/O threads).
  [[nodiscard]] Result<Publisher> start(const Caller& caller, const std::string& rig, const std::string& case_name, int case_version,
                                        std::optional<std::int64_t> assignment_id);
  // One message from the rig. Ok with nothing to do, or an error line to send back (the stream
  // stays open). Sets publisher.ended on {"type": "end"}. No store access.
  [[nodiscard]] Status message(Publisher& publisher, std::string_view text);
  // True when the store's last_seen should be refreshed now (then call touch off the I/O threads).
  [[nodiscard]] bool touch_due(Publisher& publisher);
  void touch(const Publisher& publisher);
  // Refreshes the store claim of every stream open on this instance whose claim is due
  // (touch_every_us), frames or not: a silent stream keeps its rig name on every instance.
  // Called on the server's sweep. Uses the store.
  void keep_claims();
  // The stream closed (cleanly or not): forget the claim, tell supervisors. Uses the store.
  void finish(Publisher& publisher);
  // The account is deleted: its streams on this instance end now (their further messages end
  // them: message() sets `ended` and publishes nothing) and supervisors are told each ended. The
  // store's claims went with the account. Answers how many streams ended.
  int forget_user(std::int64_t user_id);

  // Which rigs the caller may see now (trainees: their own). Uses the store.
  [[nodiscard]] std::vector<LiveRig> rigs(const Caller& caller);
  [[nodiscard]] nlohmann::json rigs_message(const Caller& caller);
  // Checks a watch request; answers the rigs the caller may watch, or 403 naming the first it
  // may not. Uses the store for trainees only.
  [[nodiscard]] Result<std::vector<std::string>> allowed(const Caller& caller, const std::vector<std::string>& rigs);

  [[nodiscard]] static nlohmann::json rig_json(const LiveRig& rig);

 private:
  Store& store_;
  Clock& clock_;
  LiveBus& bus_;
  std::string instance_;
  LiveOptions options_;
  // The streams open on this instance: rig -> its user and stream id. A rig name stays bound to
  // its stream until the stream ends, whatever its claim's age in the store.
  struct OpenStream {
    std::int64_t user_id = 0;
    std::uint64_t id = 0;
    std::int64_t claimed_us = 0;  // the store claim's last refresh by this instance
  };
  std::mutex streams_mutex_;
  std::map<std::string, OpenStream> open_streams_;
  std::uint64_t next_stream_id_ = 0;
};

}  // namespace cathbox::server
