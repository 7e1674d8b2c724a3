// GET /audit (admins), and the entry each audited handler appends (api_call.hpp's `audit`).
#include "api_call.hpp"
#include "server/audit_log.hpp"
#include "server/iso_time.hpp"

namespace cathbox::server::api {

AuditEntry audit_entry(Call& call) {
  AuditEntry e;
  e.at_us = call.c.clock.now_us();
  e.actor = call.caller.name;
  e.remote = call.request.remote_address.empty() ? std::string("unknown") : call.request.remote_address;
  return e;
}

void audit(Call& call, const std::string& action, const std::string& target, const std::string& detail) {
  AuditEntry e = audit_entry(call);
  e.action = action;
  e.target = target;
  e.detail = detail;
  append_audit(call.c.store.database(), e);
}

Reply list_audit(Call& call) {
  if (Status s = call.require_admin("reading the audit log"); !s) return s.error();
  AuditQuery q;
  Result<std::optional<std::int64_t>> limit = call.query_integer("limit", 1, 1000);
  if (!limit) return limit.error();
  q.limit = static_cast<int>(limit.value().value_or(100));
  if (const std::optional<std::string> since = call.query("since")) {
    q.since_us = parse_iso_time(*since);
    if (!q.since_us) return make_error(400, "query 'since': expected YYYY-MM-DD or YYYY-MM-DDTHH:MM:SSZ");
  }
  q.actor = call.query("actor");
  nlohmann::json entries = nlohmann::json::array();
  for (const AuditEntry& e : audit_entries(call.c.store.database(), q)) {
    entries.push_back({{"id", e.id},
                       {"at", iso_time(e.at_us)},
                       {"actor", e.actor},
                       {"action", e.action},
                       {"target", e.target},
                       {"detail", e.detail},
                       {"from", e.remote}});
  }
  return json_response(200, {{"entries", std::move(entries)}});
}

}  // namespace cathbox::server::api
