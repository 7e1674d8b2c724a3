#include "server/audit_log.hpp"

#include <algorithm>

namespace cathbox::server {

void append_audit(Database& db, const AuditEntry& e) {
  db.transact(TxMode::kWrite, [&](SqlSession& s) {
    (void)s.query("INSERT INTO audit_log (at_us, actor, action, target, detail, remote) VALUES ($1, $2, $3, $4, $5, $6)",
                  {e.at_us, e.actor, e.action, e.target, e.detail, e.remote});
  });
}

std::vector<AuditEntry> audit_entries(Database& db, const AuditQuery& q) {
  std::vector<AuditEntry> out;
  db.transact(TxMode::kRead, [&](SqlSession& s) {
    out.clear();
    std::string sql = "SELECT id, at_us, actor, action, target, detail, remote FROM audit_log WHERE at_us >= $1";
    std::vector<SqlValue> params{q.since_us.value_or(0)};
    if (q.actor) {
      sql += " AND actor = $2";
      params.emplace_back(*q.actor);
    }
    sql += " ORDER BY at_us DESC, id DESC LIMIT " + std::to_string(std::max(1, q.limit));
    for (const SqlRow& r : s.query(sql, params)) {
      out.push_back({r.integer(0), r.integer(1), r.text(2), r.text(3), r.text(4), r.text(5), r.text(6)});
    }
  });
  return out;
}

}  // namespace cathbox::server
