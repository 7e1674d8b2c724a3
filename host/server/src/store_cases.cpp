// The Store's case library (cases and their versions) and assignments.
#include "server/store.hpp"

#include "store_rows.hpp"

namespace cathbox::server {

using store_rows::I;
using store_rows::kAssignmentSelect;
using store_rows::kCaseColumns;
using store_rows::opt;
using store_rows::read_all;
using store_rows::read_assignment;
using store_rows::read_case;
using store_rows::read_one;
using store_rows::read_text;

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

}  // namespace cathbox::server
