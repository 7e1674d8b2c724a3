#include "server/store.hpp"

namespace cathbox::server {

namespace {

using I = std::int64_t;

SqlValue opt(const std::optional<I>& v) { return v ? SqlValue(*v) : SqlValue(nullptr); }

constexpr const char* kUserColumns = "id, name, role, password_hash, disabled, created_us";

User read_user(const SqlRow& r) {
  User u;
  u.id = r.integer(0);
  u.name = r.text(1);
  u.role = parse_role(r.text(2)).value_or(Role::kTrainee);
  u.password_hash = r.text(3);
  u.disabled = r.integer(4) != 0;
  u.created_us = r.integer(5);
  return u;
}

constexpr const char* kCaseColumns =
    "v.id, c.name, v.version, v.title, v.case_file, v.hclm_file, v.content_hash, v.raw_bytes, v.wire_bytes, "
    "v.mesh_vertices, v.mesh_triangles, v.mesh_bytes, v.uploaded_by, v.created_us";

CaseVersion read_case(const SqlRow& r) {
  CaseVersion c;
  c.id = r.integer(0);
  c.name = r.text(1);
  c.version = static_cast<int>(r.integer(2));
  c.title = r.text(3);
  c.case_file = r.text(4);
  c.hclm_file = r.text(5);
  c.content_hash = r.text(6);
  c.raw_bytes = r.integer(7);
  c.wire_bytes = r.integer(8);
  c.mesh_vertices = r.integer(9);
  c.mesh_triangles = r.integer(10);
  c.mesh_bytes = r.integer(11);
  c.uploaded_by = r.optional_integer(12);
  c.created_us = r.integer(13);
  return c;
}

constexpr const char* kAssignmentSelect =
    "SELECT a.id, a.trainee_id, u.name, c.name, a.case_version, a.criteria, a.note, a.assigned_by, a.created_us, a.due_us "
    "FROM assignments a JOIN users u ON u.id = a.trainee_id JOIN cases c ON c.id = a.case_id";

Assignment read_assignment(const SqlRow& r) {
  Assignment a;
  a.id = r.integer(0);
  a.trainee_id = r.integer(1);
  a.trainee = r.text(2);
  a.case_name = r.text(3);
  a.case_version = static_cast<int>(r.integer(4));
  a.criteria_json = r.text(5);
  a.note = r.text(6);
  a.assigned_by = r.optional_integer(7);
  a.created_us = r.integer(8);
  a.due_us = r.optional_integer(9);
  return a;
}

constexpr const char* kResultSelect =
    "SELECT r.id, r.content_hash, r.user_id, u.name, r.assignment_id, r.case_name, r.case_version_id, r.started_us, "
    "r.duration_ms, r.uploaded_us, r.record_bytes, r.passed, r.metrics, r.run_hash, r.complete, r.record_gone_us FROM results r JOIN users u ON u.id = r.user_id";

ResultRow read_result(const SqlRow& r) {
  ResultRow x;
  x.id = r.integer(0);
  x.content_hash = r.text(1);
  x.user_id = r.integer(2);
  x.user = r.text(3);
  x.assignment_id = r.optional_integer(4);
  x.case_name = r.text(5);
  x.case_version_id = r.optional_integer(6);
  x.started_us = r.integer(7);
  x.duration_ms = r.integer(8);
  x.uploaded_us = r.integer(9);
  x.record_bytes = r.integer(10);
  if (!r.is_null(11)) x.passed = r.integer(11) != 0;
  x.metrics_json = r.text(12);
  if (!r.is_null(13)) x.run_hash = r.text(13);
  x.complete = r.integer(14) != 0;
  x.record_gone_us = r.optional_integer(15);
  return x;
}

constexpr const char* kLiveSelect =
    "SELECT l.rig, l.user_id, u.name, l.case_name, l.case_version, l.assignment_id, l.instance, l.started_us, l.last_seen_us "
    "FROM live_rigs l JOIN users u ON u.id = l.user_id";

LiveRig read_live(const SqlRow& r) {
  LiveRig l;
  l.rig = r.text(0);
  l.user_id = r.integer(1);
  l.user = r.text(2);
  l.case_name = r.text(3);
  l.case_version = static_cast<int>(r.integer(4));
  l.assignment_id = r.optional_integer(5);
  l.instance = r.text(6);
  l.started_us = r.integer(7);
  l.last_seen_us = r.integer(8);
  return l;
}

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

std::string read_text(const SqlRow& r) { return r.text(0); }
MetricValue read_metric(const SqlRow& r) { return MetricValue{r.text(0), r.real(1)}; }

// Every login failure of the account `name`, from any address (keys "NAME@ADDRESS").
void delete_account_login_failures(SqlSession& s, const std::string& name) {
  std::string pattern;
  for (const char c : name) {
    if (c == '%' || c == '_' || c == '\\') pattern += '\\';
    pattern += c;
  }
  pattern += "@%";
  (void)s.query("DELETE FROM login_failures WHERE name = $1 OR name LIKE $2 ESCAPE '\\'", {name, pattern});
}

}  // namespace

// ---- users -------------------------------------------------------------------------------

std::optional<User> Store::create_user(const std::string& name, Role role, const std::string& password_hash, I now_us) {
  std::optional<User> out;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    const auto row = s.query_one(
        std::string("INSERT INTO users (name, role, password_hash, disabled, created_us) VALUES ($1, $2, $3, 0, $4) "
                    "ON CONFLICT (name) DO NOTHING RETURNING ") + kUserColumns,
        {name, std::string(role_name(role)), password_hash, now_us});
    if (row) out = read_user(*row);
  });
  return out;
}

std::optional<User> Store::user_by_name(const std::string& name) {
  return read_one(*db_, std::string("SELECT ") + kUserColumns + " FROM users WHERE name = $1", {name}, read_user);
}

std::optional<User> Store::user_by_id(I id) {
  return read_one(*db_, std::string("SELECT ") + kUserColumns + " FROM users WHERE id = $1", {id}, read_user);
}

std::vector<User> Store::list_users() {
  return read_all(*db_, std::string("SELECT ") + kUserColumns + " FROM users ORDER BY name", {}, read_user);
}

int Store::count_admins() {
  int n = 0;
  db_->transact(TxMode::kRead, [&](SqlSession& s) {
    n = static_cast<int>(s.query_one("SELECT COUNT(*) FROM users WHERE role = 'admin' AND disabled = 0")->integer(0));
  });
  return n;
}

bool Store::update_user(I id, std::optional<Role> role, std::optional<std::string> password_hash, std::optional<bool> disabled) {
  return update_user_keeping_an_admin(id, role, std::move(password_hash), disabled, false) == UserUpdate::kDone;
}

Store::UserUpdate Store::update_user_keeping_an_admin(I id, std::optional<Role> role, std::optional<std::string> password_hash,
                                                      std::optional<bool> disabled, bool keep_an_admin) {
  UserUpdate outcome = UserUpdate::kNotFound;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    outcome = UserUpdate::kNotFound;
    const std::optional<SqlRow> row = s.query_one("SELECT role, disabled FROM users WHERE id = $1", {id});
    if (!row) return;
    const bool active_admin = row->text(0) == "admin" && row->integer(1) == 0;
    const bool loses_admin = active_admin && ((role && *role != Role::kAdmin) || disabled.value_or(false));
    if (keep_an_admin && loses_admin) {
      // The count and the change in one transaction: two admins demoting each other at once
      // cannot both see the other still an admin (PostgreSQL: the admins' rows are locked;
      // SQLite: write transactions run one at a time).
      const char* others = s.dialect() == SqlDialect::kPostgresql
                               ? "SELECT id FROM users WHERE role = 'admin' AND disabled = 0 AND id <> $1 FOR UPDATE"
                               : "SELECT id FROM users WHERE role = 'admin' AND disabled = 0 AND id <> $1";
      if (s.query(others, {id}).empty()) {
        outcome = UserUpdate::kLastAdmin;
        return;
      }
    }
    outcome = UserUpdate::kDone;
    if (role) (void)s.query("UPDATE users SET role = $1 WHERE id = $2", {std::string(role_name(*role)), id});
    if (password_hash) (void)s.query("UPDATE users SET password_hash = $1 WHERE id = $2", {*password_hash, id});
    if (disabled) (void)s.query("UPDATE users SET disabled = $1 WHERE id = $2", {I{*disabled ? 1 : 0}, id});
  });
  return outcome;
}

// ---- tokens --------------------------------------------------------------------------------

void Store::insert_token(const std::string& token_hash, I user_id, I issued_us, I expires_us) {
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    (void)s.query("INSERT INTO tokens (token_hash, user_id, issued_us, expires_us) VALUES ($1, $2, $3, $4)",
                  {token_hash, user_id, issued_us, expires_us});
  });
}

std::optional<TokenOwner> Store::token_owner(const std::string& token_hash) {
  std::optional<TokenOwner> out;
  db_->transact(TxMode::kRead, [&](SqlSession& s) {
    const auto row = s.query_one(
        "SELECT u.id, u.name, u.role, u.password_hash, u.disabled, u.created_us, t.expires_us "
        "FROM tokens t JOIN users u ON u.id = t.user_id WHERE t.token_hash = $1",
        {token_hash});
    if (row) out = TokenOwner{read_user(*row), row->integer(6)};
  });
  return out;
}

void Store::delete_token(const std::string& token_hash) {
  db_->transact(TxMode::kWrite, [&](SqlSession& s) { (void)s.query("DELETE FROM tokens WHERE token_hash = $1", {token_hash}); });
}

void Store::delete_user_tokens(I user_id) {
  db_->transact(TxMode::kWrite, [&](SqlSession& s) { (void)s.query("DELETE FROM tokens WHERE user_id = $1", {user_id}); });
}

int Store::purge_tokens(I now_us) {
  int n = 0;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    n = static_cast<int>(s.query("DELETE FROM tokens WHERE expires_us <= $1 RETURNING 1", {now_us}).size());
  });
  return n;
}

// ---- login failures ------------------------------------------------------------------------

void Store::record_login_failure(const std::string& name, I at_us) {
  db_->transact(TxMode::kWrite,
                [&](SqlSession& s) { (void)s.query("INSERT INTO login_failures (name, at_us) VALUES ($1, $2)", {name, at_us}); });
}

int Store::login_failures_since(const std::string& name, I since_us) {
  int n = 0;
  db_->transact(TxMode::kRead, [&](SqlSession& s) {
    n = static_cast<int>(s.query_one("SELECT COUNT(*) FROM login_failures WHERE name = $1 AND at_us >= $2", {name, since_us})->integer(0));
  });
  return n;
}

void Store::clear_login_failures(const std::string& name) {
  db_->transact(TxMode::kWrite, [&](SqlSession& s) { (void)s.query("DELETE FROM login_failures WHERE name = $1", {name}); });
}

void Store::clear_account_login_failures(const std::string& name) {
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    delete_account_login_failures(s, name);
  });
}

int Store::purge_login_failures(I before_us) {
  int n = 0;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    n = static_cast<int>(s.query("DELETE FROM login_failures WHERE at_us < $1 RETURNING 1", {before_us}).size());
  });
  return n;
}

// ---- cases ---------------------------------------------------------------------------------

CaseInsert Store::insert_case_version(const std::string& name, const CaseVersion& meta, const std::string& bundle, I now_us) {
  CaseInsert out;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    (void)s.query("INSERT INTO cases (name, created_us) VALUES ($1, $2) ON CONFLICT (name) DO NOTHING", {name, now_us});
    const I case_id = s.query_one("SELECT id FROM cases WHERE name = $1", {name})->integer(0);
    const auto newest = s.query_one(std::string("SELECT ") + kCaseColumns +
                                        " FROM case_versions v JOIN cases c ON c.id = v.case_id WHERE v.case_id = $1 "
                                        "ORDER BY v.version DESC LIMIT 1",
                                    {case_id});
    if (newest && newest->text(6) == meta.content_hash) {
      out.version = read_case(*newest);
      out.created = false;
      return;
    }
    const I next = newest ? newest->integer(2) + 1 : 1;
    const I id = s.query_one(
                      "INSERT INTO case_versions (case_id, version, title, case_file, hclm_file, content_hash, raw_bytes, wire_bytes, "
                      "mesh_vertices, mesh_triangles, mesh_bytes, uploaded_by, created_us) "
                      "VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12, $13) RETURNING id",
                      {case_id, next, meta.title, meta.case_file, meta.hclm_file, meta.content_hash, meta.raw_bytes, meta.wire_bytes,
                       meta.mesh_vertices, meta.mesh_triangles, meta.mesh_bytes, opt(meta.uploaded_by), now_us})
                     ->integer(0);
    (void)s.query("INSERT INTO case_bundles (version_id, bundle) VALUES ($1, $2)", {id, Blob{bundle}});
    out.version = meta;
    out.version.id = id;
    out.version.name = name;
    out.version.version = static_cast<int>(next);
    out.version.created_us = now_us;
    out.created = true;
  });
  return out;
}

std::vector<CaseVersion> Store::list_cases() {
  return read_all(*db_,
                  std::string("SELECT ") + kCaseColumns +
                      " FROM case_versions v JOIN cases c ON c.id = v.case_id "
                      "WHERE v.version = (SELECT MAX(w.version) FROM case_versions w WHERE w.case_id = v.case_id) ORDER BY c.name",
                  {}, read_case);
}

std::vector<CaseVersion> Store::case_versions(const std::string& name) {
  return read_all(*db_,
                  std::string("SELECT ") + kCaseColumns + " FROM case_versions v JOIN cases c ON c.id = v.case_id WHERE c.name = $1 ORDER BY v.version",
                  {name}, read_case);
}

std::optional<CaseVersion> Store::case_version(const std::string& name, int version) {
  const std::string base = std::string("SELECT ") + kCaseColumns + " FROM case_versions v JOIN cases c ON c.id = v.case_id WHERE c.name = $1";
  if (version == 0) return read_one(*db_, base + " ORDER BY v.version DESC LIMIT 1", {name}, read_case);
  return read_one(*db_, base + " AND v.version = $2", {name, I{version}}, read_case);
}

std::optional<CaseVersion> Store::case_version_by_hash(const std::string& content_hash) {
  return read_one(*db_,
                  std::string("SELECT ") + kCaseColumns +
                      " FROM case_versions v JOIN cases c ON c.id = v.case_id WHERE v.content_hash = $1 ORDER BY v.id LIMIT 1",
                  {content_hash}, read_case);
}

std::optional<std::string> Store::case_bundle(I version_id) {
  return read_one(*db_, "SELECT bundle FROM case_bundles WHERE version_id = $1", {version_id}, read_text);
}

// ---- assignments ---------------------------------------------------------------------------

std::optional<Assignment> Store::insert_assignment(const Assignment& a, I now_us) {
  std::optional<Assignment> out;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    const auto c = s.query_one("SELECT id FROM cases WHERE name = $1", {a.case_name});
    if (!c) return;
    const I id = s.query_one(
                      "INSERT INTO assignments (trainee_id, case_id, case_version, criteria, note, assigned_by, created_us, due_us) "
                      "VALUES ($1, $2, $3, $4, $5, $6, $7, $8) RETURNING id",
                      {a.trainee_id, c->integer(0), I{a.case_version}, a.criteria_json, a.note, opt(a.assigned_by), now_us, opt(a.due_us)})
                     ->integer(0);
    const auto row = s.query_one(std::string(kAssignmentSelect) + " WHERE a.id = $1", {id});
    out = read_assignment(*row);
  });
  return out;
}

std::optional<Assignment> Store::assignment(I id) {
  return read_one(*db_, std::string(kAssignmentSelect) + " WHERE a.id = $1", {id}, read_assignment);
}

std::vector<Assignment> Store::list_assignments(std::optional<I> trainee_id) {
  if (trainee_id) return read_all(*db_, std::string(kAssignmentSelect) + " WHERE a.trainee_id = $1 ORDER BY a.id", {*trainee_id}, read_assignment);
  return read_all(*db_, std::string(kAssignmentSelect) + " ORDER BY a.id", {}, read_assignment);
}

bool Store::delete_assignment(I id) {
  bool deleted = false;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    // A verdict means "passed this assignment's criteria": with the assignment gone it means
    // nothing, so it goes too (the results stay, with their metrics).
    (void)s.query("UPDATE results SET passed = NULL WHERE assignment_id = $1", {id});
    deleted = !s.query("DELETE FROM assignments WHERE id = $1 RETURNING id", {id}).empty();
  });
  return deleted;
}

std::optional<std::vector<std::string>> Store::delete_user(I id) {
  std::optional<std::vector<std::string>> hashes;
  db_->transact(TxMode::kWrite, [&](SqlSession& s) {
    hashes.reset();
    const std::optional<SqlRow> user = s.query_one("SELECT name FROM users WHERE id = $1", {id});
    if (!user) return;
    const std::string name = user->text(0);
    hashes.emplace();
    for (const SqlRow& r : s.query("SELECT content_hash FROM results WHERE user_id = $1", {id})) hashes->push_back(r.text(0));
    // Results, records, metrics, assignments for them, tokens and live rigs go by ON DELETE CASCADE.
    (void)s.query("DELETE FROM users WHERE id = $1", {id});
    delete_account_login_failures(s, name);
  });
  return hashes;
}

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
