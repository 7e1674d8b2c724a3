// The Store's row readers: one row of each table's SELECT (store_rows.hpp) as its type.
#include "store_rows.hpp"

namespace cathbox::server::store_rows {

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

std::string read_text(const SqlRow& r) { return r.text(0); }
MetricValue read_metric(const SqlRow& r) { return MetricValue{r.text(0), r.real(1)}; }

}  // namespace cathbox::server::store_rows
