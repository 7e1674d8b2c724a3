#include "server/live_service.hpp"

#include <algorithm>

#include "server/iso_time.hpp"
#include "server/json_input.hpp"
#include "server/live_schema.hpp"

namespace cathbox::server {

LiveService::LiveService(Store& store, Clock& clock, LiveBus& bus, std::string instance, LiveOptions options)
    : store_(store), clock_(clock), bus_(bus), instance_(std::move(instance)), options_(options) {}

nlohmann::json LiveService::rig_json(const LiveRig& r) {
  nlohmann::json j = {{"rig", r.rig},
                      {"user", r.user},
                      {"case", r.case_name},
                      {"case_version", r.case_version},
                      {"instance", r.instance},
                      {"started_at", iso_time(r.started_us)},
                      {"last_seen_at", iso_time(r.last_seen_us)}};
  j["assignment"] = r.assignment_id ? nlohmann::json(*r.assignment_id) : nlohmann::json(nullptr);
  return j;
}

Result<Publisher> LiveService::start(const Caller& caller, const std::string& rig, const std::string& case_name, int case_version,
                                     std::optional<std::int64_t> assignment_id) {
  if (const std::string bad = check_slug(rig); !bad.empty()) return make_error(400, "rig: " + bad);
  if (const std::string bad = check_slug(case_name); !bad.empty()) return make_error(400, "query 'case': " + bad);
  if (assignment_id) {
    const std::optional<Assignment> a = store_.assignment(*assignment_id);
    if (!a || (a->trainee_id != caller.user_id && !can_supervise(caller.role))) {
      return make_error(404, "query 'assignment': no assignment " + std::to_string(*assignment_id) + " for you");
    }
  }
  const std::int64_t now = clock_.now_us();
  Publisher p;
  p.caller = caller;
  p.rig = LiveRig{rig, caller.user_id, caller.name, case_name, case_version, assignment_id, instance_, now, now};
  {
    const std::lock_guard lock(streams_mutex_);
    const auto open = open_streams_.find(rig);
    const bool taken = open != open_streams_.end() && open->second.user_id != caller.user_id;
    if (taken || !store_.claim_live_rig(p.rig, now - options_.stale_after_us)) {
      return make_error(409, "rig '" + rig + "' is streaming for another user");
    }
    p.stream_id = ++next_stream_id_;
    open_streams_[rig] = OpenStream{caller.user_id, p.stream_id, now};
  }
  p.last_touch_us = now;
  p.frame_tokens = options_.max_frames_per_s;
  p.tokens_at_us = now;
  const nlohmann::json started = {{"type", "started"}, {"rig", rig_json(p.rig)}};
  bus_.publish_event(std::make_shared<const std::string>(started.dump()));
  return p;
}

Status LiveService::message(Publisher& p, std::string_view text) {
  Result<ParsedPublisherMessage> parsed = parse_publisher_message(text);
  if (!parsed) return parsed.error();
  if (parsed.value().kind == PublisherMessage::kEnd) {
    p.ended = true;
    return Ok{};
  }
  {
    // A stream forgotten (its account deleted) carries nothing more.
    const std::lock_guard lock(streams_mutex_);
    const auto open = open_streams_.find(p.rig.rig);
    if (open == open_streams_.end() || open->second.id != p.stream_id) {
      p.ended = true;
      return Ok{};
    }
  }
  const std::int64_t now = clock_.now_us();
  p.frame_tokens = std::min(options_.max_frames_per_s,
                            p.frame_tokens + static_cast<double>(now - p.tokens_at_us) * 1e-6 * options_.max_frames_per_s);
  p.tokens_at_us = now;
  if (p.frame_tokens < 1.0) {
    ++p.dropped;
    return Ok{};
  }
  p.frame_tokens -= 1.0;
  ++p.frames;
  bus_.publish_frame(p.rig.rig, std::make_shared<const std::string>(frame_envelope(p.rig.rig, now, parsed.value().frame)));
  return Ok{};
}

bool LiveService::touch_due(Publisher& p) {
  const std::int64_t now = clock_.now_us();
  if (now - p.last_touch_us < options_.touch_every_us) return false;
  p.last_touch_us = now;
  return true;
}

void LiveService::touch(const Publisher& p) { store_.touch_live_rig(p.rig.rig, instance_, clock_.now_us()); }

void LiveService::keep_claims() {
  const std::int64_t now = clock_.now_us();
  std::vector<std::string> due;
  {
    const std::lock_guard lock(streams_mutex_);
    for (auto& [rig, open] : open_streams_) {
      if (now - open.claimed_us < options_.touch_every_us) continue;
      open.claimed_us = now;
      due.push_back(rig);
    }
  }
  for (const std::string& rig : due) store_.touch_live_rig(rig, instance_, now);
}

void LiveService::finish(Publisher& p) {
  {
    // Only the rig's current stream ends it: an older stream of the same user (replaced by a
    // reconnection) leaves the claim and the watchers alone.
    const std::lock_guard lock(streams_mutex_);
    const auto open = open_streams_.find(p.rig.rig);
    if (open == open_streams_.end() || open->second.id != p.stream_id) return;
    open_streams_.erase(open);
  }
  store_.end_live_rig(p.rig.rig, instance_);
  const nlohmann::json ended = {{"type", "ended"}, {"rig", p.rig.rig}};
  bus_.publish_event(std::make_shared<const std::string>(ended.dump()));
}

int LiveService::forget_user(std::int64_t user_id) {
  std::vector<std::string> ended_rigs;
  {
    const std::lock_guard lock(streams_mutex_);
    for (auto it = open_streams_.begin(); it != open_streams_.end();) {
      if (it->second.user_id == user_id) {
        ended_rigs.push_back(it->first);
        it = open_streams_.erase(it);
      } else {
        ++it;
      }
    }
  }
  for (const std::string& rig : ended_rigs) {
    const nlohmann::json ended = {{"type", "ended"}, {"rig", rig}};
    bus_.publish_event(std::make_shared<const std::string>(ended.dump()));
  }
  return static_cast<int>(ended_rigs.size());
}

std::vector<LiveRig> LiveService::rigs(const Caller& caller) {
  std::vector<LiveRig> all = store_.live_rigs(clock_.now_us() - options_.stale_after_us);
  if (!can_supervise(caller.role)) std::erase_if(all, [&](const LiveRig& r) { return r.user_id != caller.user_id; });
  return all;
}

nlohmann::json LiveService::rigs_message(const Caller& caller) {
  nlohmann::json list = nlohmann::json::array();
  for (const LiveRig& r : rigs(caller)) list.push_back(rig_json(r));
  return {{"type", "rigs"}, {"rigs", std::move(list)}};
}

Result<std::vector<std::string>> LiveService::allowed(const Caller& caller, const std::vector<std::string>& rigs) {
  if (can_supervise(caller.role)) return rigs;
  for (const std::string& rig : rigs) {
    const std::optional<LiveRig> live = store_.live_rig(rig);
    if (!live || live->user_id != caller.user_id) return make_error(403, "rig '" + rig + "': trainees may watch only their own rig");
  }
  return rigs;
}

}  // namespace cathbox::server
