// The Store's results (with their metrics index and records) and live rigs.
#include "server/store.hpp"

#include "store_rows.hpp"

namespace cathbox::server {

using store_rows::I;
using store_rows::kLiveSelect;
using store_rows::kResultSelect;
using store_rows::opt;
using store_rows::read_all;
using store_rows::read_live;
using store_rows::read_metric;
using store_rows::read_one;
using store_rows::read_result;
using store_rows::read_text;

// ---- results -------------------------------------------------------------------------------

ResultInsert Store::insert_result(const ResultRow& row, const std::vector<MetricValue>& metrics, const std::string& record) {
  ResultInsert out;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    const auto inserted = s.query_one(
        "INSERT INTO results (content_hash, user_id, assignment_id, case_name, case_version_id, started_us, duration_ms, "
        "uploaded_us, record_bytes, passed, metrics, run_hash, complete) VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, "
        "$12, $13) ON CONFLICT DO NOTHING RETURNING id",
        {row.content_hash, row.user_id, opt(row.assignment_id), row.case_name, opt(row.case_version_id), row.started_us,
         row.duration_ms, row.uploaded_us, row.record_bytes, row.passed ? SqlValue(I{*row.passed ? 1 : 0}) : SqlValue(nullptr),
         row.metrics_json, row.run_hash.empty() ? SqlValue(nullptr) : SqlValue(row.run_hash), I{row.complete ? 1 : 0}});
    if (inserted) {
      const I id = inserted->integer(0);
      (void)s.query("INSERT INTO result_records (result_id, record) VALUES ($1, $2)", {id, Blob{record}});
      for (const MetricValue& m : metrics) {
        (void)s.query("INSERT INTO result_metrics (result_id, name, value) VALUES ($1, $2, $3)", {id, m.name, m.value});
      }
      out.created = true;
    }
    // The same bytes, or (a conflict on the run) the same run re-encoded.
    const auto stored = s.query_one(std::string(kResultSelect) + " WHERE r.content_hash = $1 OR r.run_hash = $2 ORDER BY r.id LIMIT 1",
                                    {row.content_hash, row.run_hash});
    out.row = read_result(*stored);
  });
  return out;
}

std::optional<ResultRow> Store::result(I id) {
  return read_one(*db_, std::string(kResultSelect) + " WHERE r.id = $1", {id}, read_result);
}

std::optional<ResultRow> Store::result_by_hash(const std::string& content_hash) {
  return read_one(*db_, std::string(kResultSelect) + " WHERE r.content_hash = $1", {content_hash}, read_result);
}

std::optional<ResultRow> Store::result_by_run(const std::string& run_hash) {
  return read_one(*db_, std::string(kResultSelect) + " WHERE r.run_hash = $1", {run_hash}, read_result);
}

std::vector<ResultRow> Store::list_results(const ResultFilter& f) {
  // The WHERE clause is assembled from fixed fragments; every value is a parameter.
  std::string sql = kResultSelect;
  std::vector<SqlValue> params;
  std::vector<std::string> where;
  const auto param = [&](SqlValue v) {
    params.push_back(std::move(v));
    return "$" + std::to_string(params.size());
  };
  if (f.user_id) where.push_back("r.user_id = " + param(*f.user_id));
  if (f.case_name) where.push_back("r.case_name = " + param(*f.case_name));
  if (f.assignment_id) where.push_back("r.assignment_id = " + param(*f.assignment_id));
  if (f.since_us) where.push_back("r.uploaded_us >= " + param(*f.since_us));
  if (f.until_us) where.push_back("r.uploaded_us < " + param(*f.until_us));
  if (f.passed) where.push_back("r.passed = " + param(I{*f.passed ? 1 : 0}));
  for (const MetricRange& m : f.metrics) {
    std::string cond = "EXISTS (SELECT 1 FROM result_metrics m WHERE m.result_id = r.id AND m.name = " + param(m.name);
    if (m.min) cond += " AND m.value >= " + param(*m.min);
    if (m.max) cond += " AND m.value <= " + param(*m.max);
    where.push_back(cond + ")");
  }
  for (std::size_t i = 0; i < where.size(); ++i) sql += (i == 0 ? " WHERE " : " AND ") + where[i];
  sql += " ORDER BY r.uploaded_us DESC, r.id DESC LIMIT " + param(I{f.limit});
  sql += " OFFSET " + param(I{f.offset});
  return read_all(*db_, sql, params, read_result);
}

std::vector<MetricValue> Store::result_metrics(I result_id) {
  return read_all(*db_, "SELECT name, value FROM result_metrics WHERE result_id = $1 ORDER BY name", {result_id}, read_metric);
}

std::vector<std::string> Store::drop_records_uploaded_before(I before_us, I now_us) {
  std::vector<std::string> hashes;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    hashes.clear();
    const std::vector<SqlRow> old =
        s.query("SELECT id, content_hash FROM results WHERE uploaded_us < $1 AND record_gone_us IS NULL", {before_us});
    for (const SqlRow& r : old) {
      (void)s.query("DELETE FROM result_records WHERE result_id = $1", {r.integer(0)});
      (void)s.query("UPDATE results SET record_gone_us = $1 WHERE id = $2", {now_us, r.integer(0)});
      hashes.push_back(r.text(1));
    }
  });
  return hashes;
}

std::optional<std::string> Store::result_record(I result_id) {
  return read_one(*db_, "SELECT record FROM result_records WHERE result_id = $1", {result_id}, read_text);
}

// ---- live rigs -----------------------------------------------------------------------------

bool Store::claim_live_rig(const LiveRig& rig, I stale_before_us) {
  bool claimed = false;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    const auto row = s.query_one("SELECT user_id, last_seen_us FROM live_rigs WHERE rig = $1", {rig.rig});
    if (row && row->integer(0) != rig.user_id && row->integer(1) >= stale_before_us) return;
    (void)s.query(
        "INSERT INTO live_rigs (rig, user_id, case_name, case_version, assignment_id, instance, started_us, last_seen_us) "
        "VALUES ($1, $2, $3, $4, $5, $6, $7, $8) ON CONFLICT (rig) DO UPDATE SET user_id = excluded.user_id, "
        "case_name = excluded.case_name, case_version = excluded.case_version, assignment_id = excluded.assignment_id, "
        "instance = excluded.instance, started_us = excluded.started_us, last_seen_us = excluded.last_seen_us",
        {rig.rig, rig.user_id, rig.case_name, I{rig.case_version}, opt(rig.assignment_id), rig.instance, rig.started_us,
         rig.last_seen_us});
    claimed = true;
  });
  return claimed;
}

void Store::touch_live_rig(const std::string& rig, const std::string& instance, I now_us) {
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    (void)s.query("UPDATE live_rigs SET last_seen_us = $1 WHERE rig = $2 AND instance = $3", {now_us, rig, instance});
  });
}

void Store::end_live_rig(const std::string& rig, const std::string& instance) {
  db_->transact(TxMode::kWrite,
                [&](SqlSession& s) { (void)s.query("DELETE FROM live_rigs WHERE rig = $1 AND instance = $2", {rig, instance}); });
}

std::vector<LiveRig> Store::live_rigs(I seen_since_us) {
  return read_all(*db_, std::string(kLiveSelect) + " WHERE l.last_seen_us >= $1 ORDER BY l.rig", {seen_since_us}, read_live);
}

std::optional<LiveRig> Store::live_rig(const std::string& rig) {
  return read_one(*db_, std::string(kLiveSelect) + " WHERE l.rig = $1", {rig}, read_live);
}

I Store::insert_live_overflow(const std::string& payload, I now_us) {
  I id = 0;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    id = s.query_one("INSERT INTO live_overflow (payload, created_us) VALUES ($1, $2) RETURNING id", {payload, now_us})->integer(0);
  });
  return id;
}

std::optional<std::string> Store::live_overflow(I id) {
  return read_one(*db_, "SELECT payload FROM live_overflow WHERE id = $1", {id}, read_text);
}

int Store::purge_live_overflow(I before_us) {
  int n = 0;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    n = static_cast<int>(s.query("DELETE FROM live_overflow WHERE created_us < $1 RETURNING 1", {before_us}).size());
  });
  return n;
}

}  // namespace cathbox::server
