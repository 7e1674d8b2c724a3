#pragma once
// The training centre's data, typed: users, tokens, login failures, the case library,
// assignments, results with their metrics index, and live rigs. One class over the Database
// interface: the same statements run on SQLite and PostgreSQL (see sql.hpp), and both pass the
// same test suite (tests/host/server/store_test.cpp).
//
// Times are microseconds since the Unix epoch (`_us`), passed in by the caller so tests run in
// virtual time. Every method is one transaction; database failures throw StoreError.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "server/role.hpp"
#include "server/sql.hpp"

namespace cathbox::server {

struct User {
  std::int64_t id = 0;
  std::string name;
  Role role = Role::kTrainee;
  std::string password_hash;  // Argon2id encoded string
  bool disabled = false;
  std::int64_t created_us = 0;
};

struct TokenOwner {
  User user;
  std::int64_t expires_us = 0;
};

struct CaseVersion {
  std::int64_t id = 0;  // of this version
  std::string name;     // the case's name in the library
  int version = 0;      // 1, 2, ...
  std::string title;    // the case file's `name` line
  std::string case_file;
  std::string hclm_file;     // empty for analytic-tube cases
  std::string content_hash;  // SHA-256 of the uncompressed bundle
  std::int64_t raw_bytes = 0;   // case + HCLM text
  std::int64_t wire_bytes = 0;  // the zstd bundle a download sends
  std::int64_t mesh_vertices = 0;
  std::int64_t mesh_triangles = 0;
  std::int64_t mesh_bytes = 0;  // the level-2 mesh the trainer builds (see case_library.hpp)
  std::optional<std::int64_t> uploaded_by;
  std::int64_t created_us = 0;
};

struct CaseInsert {
  CaseVersion version;
  bool created = false;  // false: the same content was already the newest version
};

struct Assignment {
  std::int64_t id = 0;
  std::int64_t trainee_id = 0;
  std::string trainee;
  std::string case_name;
  int case_version = 0;  // 0: whichever version is newest
  std::string criteria_json;
  std::string note;
  std::optional<std::int64_t> assigned_by;
  std::int64_t created_us = 0;
  std::optional<std::int64_t> due_us;
};

struct MetricValue {
  std::string name;
  double value = 0.0;
};

struct ResultRow {
  std::int64_t id = 0;
  std::string content_hash;  // SHA-256 of the record bytes
  std::string run_hash;      // SHA-256 of the decoded run (record_checker.hpp): one result per run
  bool complete = true;      // false: the record has no end block (cut); for debriefs, never graded
  std::int64_t user_id = 0;
  std::string user;
  std::optional<std::int64_t> assignment_id;
  std::string case_name;
  std::optional<std::int64_t> case_version_id;
  std::int64_t started_us = 0;
  std::int64_t duration_ms = 0;
  std::int64_t uploaded_us = 0;
  std::int64_t record_bytes = 0;
  std::optional<bool> passed;  // empty when the run had no assignment
  std::string metrics_json;
  // When the retention setting removed the record (the result and its metrics stay); empty
  // while the record is kept.
  std::optional<std::int64_t> record_gone_us;
};

struct ResultInsert {
  ResultRow row;
  bool created = false;  // false: a record with this content hash or run hash was already stored
};

struct MetricRange {
  std::string name;
  std::optional<double> min;
  std::optional<double> max;
};

struct ResultFilter {
  std::optional<std::int64_t> user_id;
  std::optional<std::string> case_name;
  std::optional<std::int64_t> assignment_id;
  std::optional<std::int64_t> since_us;  // uploaded at or after
  std::optional<std::int64_t> until_us;  // uploaded before
  std::optional<bool> passed;
  std::vector<MetricRange> metrics;  // each through the metrics index
  int limit = 100;
  int offset = 0;
};

struct LiveRig {
  std::string rig;
  std::int64_t user_id = 0;
  std::string user;
  std::string case_name;
  int case_version = 0;
  std::optional<std::int64_t> assignment_id;
  std::string instance;  // the server instance the rig streams to
  std::int64_t started_us = 0;
  std::int64_t last_seen_us = 0;
};

class Store {
 public:
  explicit Store(std::unique_ptr<Database> db) : db_(std::move(db)) {}
  [[nodiscard]] Database& database() { return *db_; }

  // Users. Names are unique; create returns nullopt when the name is taken.
  [[nodiscard]] std::optional<User> create_user(const std::string& name, Role role, const std::string& password_hash,
                                                std::int64_t now_us);
  [[nodiscard]] std::optional<User> user_by_name(const std::string& name);
  [[nodiscard]] std::optional<User> user_by_id(std::int64_t id);
  [[nodiscard]] std::vector<User> list_users();
  [[nodiscard]] int count_admins();
  // Changes what is given; false when there is no such user.
  bool update_user(std::int64_t id, std::optional<Role> role, std::optional<std::string> password_hash,
                   std::optional<bool> disabled);
  enum class UserUpdate { kDone, kNotFound, kLastAdmin };
  // update_user, refused (kLastAdmin, nothing changed) when `keep_an_admin` and the change would
  // leave no enabled admin; the check and the change are one transaction.
  [[nodiscard]] UserUpdate update_user_keeping_an_admin(std::int64_t id, std::optional<Role> role, std::optional<std::string> password_hash,
                                                        std::optional<bool> disabled, bool keep_an_admin);

  // Deletes the account and, in the same transaction, everything of theirs: results with their
  // records and metrics, assignments made for them, tokens, live rigs, login failures. Cases
  // and assignments they made stay (their author becomes null). Answers the content hashes of
  // the deleted records (the caller purges what it derived from them), or nullopt when there
  // is no such user.
  [[nodiscard]] std::optional<std::vector<std::string>> delete_user(std::int64_t id);

  // Bearer tokens, stored by their SHA-256 only.
  void insert_token(const std::string& token_hash, std::int64_t user_id, std::int64_t issued_us, std::int64_t expires_us);
  [[nodiscard]] std::optional<TokenOwner> token_owner(const std::string& token_hash);
  void delete_token(const std::string& token_hash);
  void delete_user_tokens(std::int64_t user_id);
  int purge_tokens(std::int64_t now_us);

  // Failed logins per account name, counted over a window (shared by every server instance).
  void record_login_failure(const std::string& name, std::int64_t at_us);
  [[nodiscard]] int login_failures_since(const std::string& name, std::int64_t since_us);
  void clear_login_failures(const std::string& name);
  // Every failure of the account, from any address (keys "NAME@ADDRESS").
  void clear_account_login_failures(const std::string& name);
  int purge_login_failures(std::int64_t before_us);

  // The case library. insert_case_version adds version n+1 unless the newest version already
  // has this content hash (then it answers that one, created = false).
  [[nodiscard]] CaseInsert insert_case_version(const std::string& name, const CaseVersion& meta, const std::string& bundle,
                                               std::int64_t now_us);
  [[nodiscard]] std::vector<CaseVersion> list_cases();  // the newest version of each case
  [[nodiscard]] std::vector<CaseVersion> case_versions(const std::string& name);
  // version 0: the newest.
  [[nodiscard]] std::optional<CaseVersion> case_version(const std::string& name, int version);
  [[nodiscard]] std::optional<CaseVersion> case_version_by_hash(const std::string& content_hash);
  [[nodiscard]] std::optional<std::string> case_bundle(std::int64_t version_id);

  // Assignments. insert answers nullopt when the case does not exist.
  [[nodiscard]] std::optional<Assignment> insert_assignment(const Assignment& a, std::int64_t now_us);
  [[nodiscard]] std::optional<Assignment> assignment(std::int64_t id);
  [[nodiscard]] std::vector<Assignment> list_assignments(std::optional<std::int64_t> trainee_id);
  bool delete_assignment(std::int64_t id);

  // Results: the record, its metrics as JSON and in the index. Idempotent by content hash.
  [[nodiscard]] ResultInsert insert_result(const ResultRow& row, const std::vector<MetricValue>& metrics, const std::string& record);
  [[nodiscard]] std::optional<ResultRow> result(std::int64_t id);
  [[nodiscard]] std::optional<ResultRow> result_by_hash(const std::string& content_hash);
  [[nodiscard]] std::optional<ResultRow> result_by_run(const std::string& run_hash);
  [[nodiscard]] std::vector<ResultRow> list_results(const ResultFilter& filter);
  [[nodiscard]] std::vector<MetricValue> result_metrics(std::int64_t result_id);
  [[nodiscard]] std::optional<std::string> result_record(std::int64_t result_id);
  // The retention setting: removes the records of results uploaded before `before_us` (one
  // transaction) and marks those results record_gone_us = now_us; the results and their metrics
  // stay. Answers the removed records' content hashes (the caller purges what derives from them).
  [[nodiscard]] std::vector<std::string> drop_records_uploaded_before(std::int64_t before_us, std::int64_t now_us);

  // Live rigs (a row while a rig streams; last_seen refreshed every few seconds).
  // claim_live_rig answers false when another user streams on this rig name and was seen
  // after `stale_before_us`.
  [[nodiscard]] bool claim_live_rig(const LiveRig& rig, std::int64_t stale_before_us);
  void touch_live_rig(const std::string& rig, const std::string& instance, std::int64_t now_us);
  void end_live_rig(const std::string& rig, const std::string& instance);
  [[nodiscard]] std::vector<LiveRig> live_rigs(std::int64_t seen_since_us);
  [[nodiscard]] std::optional<LiveRig> live_rig(const std::string& rig);
  // Oversized live messages for PostgreSQL's NOTIFY (8000-byte payload limit).
  [[nodiscard]] std::int64_t insert_live_overflow(const std::string& payload, std::int64_t now_us);
  [[nodiscard]] std::optional<std::string> live_overflow(std::int64_t id);
  int purge_live_overflow(std::int64_t before_us);

 private:
  std::unique_ptr<Database> db_;
};

}  // namespace cathbox::server
