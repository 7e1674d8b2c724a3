#pragma once
// The Store's rows (store.cpp, store_cases.cpp, store_results.cpp): each table's SELECT columns
// and the reader that maps one row to its type (store_rows.cpp), and one read transaction
// answering the first row or every row.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "server/store.hpp"

namespace cathbox::server::store_rows {

using I = std::int64_t;

inline SqlValue opt(const std::optional<I>& v) { return v ? SqlValue(*v) : SqlValue(nullptr); }

inline constexpr const char* kUserColumns = "id, name, role, password_hash, disabled, created_us";
User read_user(const SqlRow& r);

inline constexpr const char* kCaseColumns =
    "v.id, c.name, v.version, v.title, v.case_file, v.hclm_file, v.content_hash, v.raw_bytes, v.wire_bytes, "
    "v.mesh_vertices, v.mesh_triangles, v.mesh_bytes, v.uploaded_by, v.created_us";
CaseVersion read_case(const SqlRow& r);

inline constexpr const char* kAssignmentSelect =
    "SELECT a.id, a.trainee_id, u.name, c.name, a.case_version, a.criteria, a.note, a.assigned_by, a.created_us, a.due_us "
    "FROM assignments a JOIN users u ON u.id = a.trainee_id JOIN cases c ON c.id = a.case_id";
Assignment read_assignment(const SqlRow& r);

inline constexpr const char* kResultSelect =
    "SELECT r.id, r.content_hash, r.user_id, u.name, r.assignment_id, r.case_name, r.case_version_id, r.started_us, "
    "r.duration_ms, r.uploaded_us, r.record_bytes, r.passed, r.metrics, r.run_hash, r.complete, r.record_gone_us FROM results r JOIN users u ON u.id = r.user_id";
ResultRow read_result(const SqlRow& r);

inline constexpr const char* kLiveSelect =
    "SELECT l.rig, l.user_id, u.name, l.case_name, l.case_version, l.assignment_id, l.instance, l.started_us, l.last_seen_us "
    "FROM live_rigs l JOIN users u ON u.id = l.user_id";
LiveRig read_live(const SqlRow& r);

std::string read_text(const SqlRow& r);
MetricValue read_metric(const SqlRow& r);

// One read transaction answering the first row (or none) / every row, mapped by `read`.
template <class T>
std::optional<T> read_one(Database& db, const std::string& sql, const std::vector<SqlValue>& params, T (*read)(const SqlRow&)) {
  std::optional<T> out;
  db.transact(TxMode::kRead, [&](SqlSession& s) {
    if (const auto row = s.query_one(sql, params)) out = read(*row);
  });
  return out;
}

template <class T>
std::vector<T> read_all(Database& db, const std::string& sql, const std::vector<SqlValue>& params, T (*read)(const SqlRow&)) {
  std::vector<T> out;
  db.transact(TxMode::kRead, [&](SqlSession& s) {
    for (const SqlRow& r : s.query(sql, params)) out.push_back(read(r));
  });
  return out;
}

}  // namespace cathbox::server::store_rows
