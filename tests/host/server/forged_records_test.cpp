// Forged, copied and cut results with real session records (issue 37), and the bounds an upload
// must keep before the server meshes or replays anything:
// - a record's header must be its case: the tools and the entry the case text defines (a run
//   with another entry or other tools is refused, naming the header field);
// - the same run re-encoded (blocks uncompressed, an extra informational header field) is the
//   same result, for its trainee; for another trainee or a second assignment it is refused;
// - a cut record (no end block) is kept for debriefs marked as cut, never graded;
// - vessel points, surface triangles, record duration and replay CPU time each have a limit.
#include <gtest/gtest.h>

#include "record_files.hpp"
#include "server/case_library.hpp"
#include "support/api_fixture.hpp"

namespace cathbox::server::test {
namespace {

using nlohmann::json;

class ForgedRecordsTest : public ::testing::TestWithParam<std::string> {
 protected:
  // A centre with the y-bifurcation as "ybif", an instructor and two trainees.
  void open(UploadLimits limits = {}) {
    f_ = std::make_unique<ApiFixture>(GetParam(), make_session_checker(std::move(limits)));
    teacher_ = f_->user("teacher", Role::kInstructor);
    alice_ = f_->user("alice", Role::kTrainee);
    bob_ = f_->user("bob", Role::kTrainee);
    ASSERT_EQ(f_->upload_bundled_case("y_bifurcation", "ybif", teacher_).status, 201);
  }
  std::string assignment(const std::string& trainee) {
    const json a = f_->call_json("POST", "/api/v1/assignments", {{"trainee", trainee}, {"case", "ybif"}}, teacher_, 201);
    return "/api/v1/results?assignment=" + std::to_string(a["id"].get<int>());
  }
  std::unique_ptr<ApiFixture> f_;
  std::string teacher_, alice_, bob_;
};

TEST_P(ForgedRecordsTest, ARunWithAnotherEntryOrOtherToolsThanItsCaseIsRefusedNamingTheField) {
  open();
  // The library case's text word for word, but entered 1 mm further in.
  const std::string moved = read_all(record_left_branch([](session::SessionCase& c) { c.entry.point_mm.z += 1.0; }, "moved.cbxrec"));
  for (const std::string& target : {assignment("alice"), std::string("/api/v1/results")}) {
    const ApiResponse r = f_->call("POST", target, moved, alice_);
    EXPECT_EQ(r.status, 422) << target;
    EXPECT_EQ(error_of(r).rfind("record: header field 'entry' (", 0), 0U) << error_of(r);
    EXPECT_NE(error_of(r).find(") is not the entry of y_bifurcation.case ("), std::string::npos) << error_of(r);
  }
  // A slipperier guidewire than the case's.
  const std::string slick =
      read_all(record_left_branch([](session::SessionCase& c) { c.spec.tools[0].friction = 0.01; }, "slick.cbxrec"));
  const ApiResponse tools = f_->call("POST", assignment("alice"), slick, alice_);
  EXPECT_EQ(tools.status, 422);
  EXPECT_EQ(error_of(tools), "record: header field 'tools': tool 1 'guidewire' is not as y_bifurcation.case defines it");
  // A second tool the case does not have.
  const std::string extra = read_all(
      record_left_branch([](session::SessionCase& c) { c.spec.tools.push_back(tool::default_catheter()); }, "extra.cbxrec"));
  const ApiResponse more = f_->call("POST", "/api/v1/results", extra, alice_);
  EXPECT_EQ(more.status, 422);
  EXPECT_EQ(error_of(more), "record: header field 'tools': 2 tools, but y_bifurcation.case defines 1");
  // The genuine run counts, filed under the library version it was checked against.
  const ApiResponse genuine = f_->call("POST", assignment("alice"), read_all(record_left_branch()), alice_);
  ASSERT_EQ(genuine.status, 201) << genuine.body;
  EXPECT_EQ(json::parse(genuine.body)["case"], "ybif");
}

TEST_P(ForgedRecordsTest, TheSameRunReencodedIsOneResult) {
  open();
  const std::string first = assignment("alice");
  const std::string good = read_all(record_left_branch());
  const ApiResponse stored = f_->call("POST", first, good, alice_);
  ASSERT_EQ(stored.status, 201) << stored.body;
  const int id = json::parse(stored.body)["id"].get<int>();
  const std::string copy = reencoded(good);
  ASSERT_NE(copy, good);
  ASSERT_GT(copy.size(), good.size());  // its blocks are stored uncompressed
  const ApiResponse again = f_->call("POST", first, copy, alice_);
  EXPECT_EQ(again.status, 200) << again.body;
  EXPECT_EQ(json::parse(again.body)["id"], id);
  EXPECT_EQ(json::parse(again.body)["created"], false);
  // Another trainee's upload of the run, and a second assignment: refused.
  const ApiResponse other = f_->call("POST", "/api/v1/results", copy, bob_);
  EXPECT_EQ(other.status, 409);
  EXPECT_EQ(error_of(other), "record: this run was uploaded by another user");
  const ApiResponse second = f_->call("POST", assignment("alice"), copy, alice_);
  EXPECT_EQ(second.status, 409);
  EXPECT_EQ(error_of(second).rfind("record: already stored as result " + std::to_string(id), 0), 0U) << error_of(second);
  EXPECT_EQ(f_->call_json("GET", "/api/v1/results", nullptr, teacher_, 200)["results"].size(), 1U);
  // The same script run again later is another run (its own start time).
  const ApiResponse later = f_->call("POST", "/api/v1/results", read_all(record_left_branch({}, "later.cbxrec")), alice_);
  EXPECT_EQ(later.status, 201) << later.body;
}

TEST_P(ForgedRecordsTest, ACutRecordIsKeptMarkedCutAndNeverGraded) {
  open();
  const std::string good = read_all(record_left_branch());
  const std::string cut = cut_before_end(good);
  ASSERT_LT(cut.size(), good.size());
  const ApiResponse graded = f_->call("POST", assignment("alice"), cut, alice_);
  EXPECT_EQ(graded.status, 422);
  EXPECT_EQ(error_of(graded).rfind("record: no end block", 0), 0U) << error_of(graded);
  const ApiResponse kept = f_->call("POST", "/api/v1/results", cut, alice_);
  ASSERT_EQ(kept.status, 201) << kept.body;
  const json r = json::parse(kept.body);
  EXPECT_EQ(r["complete"], false);
  EXPECT_EQ(r["passed"], nullptr);
  EXPECT_NE(r["cut"].get<std::string>().find("never graded"), std::string::npos);
  const json detail = f_->call_json("GET", "/api/v1/results/" + std::to_string(r["id"].get<int>()), nullptr, teacher_, 200);
  EXPECT_EQ(detail["complete"], false);
  // The whole record is another result, complete.
  const ApiResponse whole = f_->call("POST", "/api/v1/results", good, alice_);
  ASSERT_EQ(whole.status, 201) << whole.body;
  EXPECT_EQ(json::parse(whole.body)["complete"], true);
  EXPECT_FALSE(json::parse(whole.body).contains("cut"));
}

TEST_P(ForgedRecordsTest, ARecordLongerThanTheLimitIsRefusedBeforeItsReplay) {
  UploadLimits limits;
  limits.max_record_duration_s = 1;
  int replays = 0;
  limits.cpu_seconds = [&replays] { return static_cast<double>(++replays); };  // counts the replay's budget checks
  open(std::move(limits));
  const ApiResponse r = f_->call("POST", "/api/v1/results", read_all(record_left_branch()), alice_);
  EXPECT_EQ(r.status, 413);
  EXPECT_EQ(error_of(r), "record: longer than the limit of 1 s of simulated time (1000 ticks of 1000 us)");
  EXPECT_EQ(replays, 0);  // no tick was replayed
}

TEST_P(ForgedRecordsTest, AReplayOverItsCpuBudgetIsStopped) {
  UploadLimits limits;
  limits.max_replay_cpu_s = 2.0;
  double cpu_s = 0.0;
  limits.cpu_seconds = [&cpu_s] { return cpu_s += 1.0; };  // a CPU clock: 1 s a read (1,000 ticks)
  open(std::move(limits));
  const ApiResponse r = f_->call("POST", "/api/v1/results", read_all(record_left_branch()), alice_);
  EXPECT_EQ(r.status, 413);
  EXPECT_EQ(error_of(r), "record: the replay passed its CPU limit of 2 s at tick 3000");
}

TEST_P(ForgedRecordsTest, AVesselOverItsPointOrTriangleLimitIsRefusedBeforeMeshing) {
  UploadLimits points;
  points.max_vessel_points = 50;
  open(points);
  const ApiResponse many = f_->call("POST", "/api/v1/results", read_all(record_left_branch()), alice_);
  EXPECT_EQ(many.status, 413);
  EXPECT_EQ(error_of(many), "record: y_bifurcation.hclm: 75 centreline points; the limit is 50");

  UploadLimits triangles;
  triangles.max_surface_triangles = 1000;
  open(triangles);
  const ApiResponse fine = f_->call("POST", "/api/v1/results", read_all(record_left_branch()), alice_);
  EXPECT_EQ(fine.status, 413);
  EXPECT_EQ(error_of(fine).rfind("record: y_bifurcation.hclm: its surface would have ", 0), 0U) << error_of(fine);
  EXPECT_NE(error_of(fine).find(" triangles or more; the limit is 1000"), std::string::npos) << error_of(fine);
}

// A case upload with a vessel of 30,000 points (the default limit is 20,000): refused from its
// text, before it is meshed (which would take minutes and gigabytes).
TEST_P(ForgedRecordsTest, ACaseUploadOverTheVesselLimitsIsRefusedBeforeMeshing) {
  open();
  std::string hclm = "s 1\n\ng 1\nl root\nf 400\np 0\nc 0\nn 30000\n";
  for (int i = 0; i < 30000; ++i) hclm += "v 0 0 " + std::to_string(i * 0.06) + " 1\n";  // 1.8 m of a 1 mm vessel
  const json body = {{"name", "huge"},
                     {"case_file", "huge.case"},
                     {"case", "cathbox-case 1\nname huge\nvessel huge.hclm\n"},
                     {"hclm_file", "huge.hclm"},
                     {"hclm", hclm}};
  const ApiResponse r = f_->call("POST", "/api/v1/cases", body.dump(), teacher_);
  EXPECT_EQ(r.status, 413);
  EXPECT_EQ(error_of(r), "huge.hclm: 30000 centreline points; the limit is 20000");
  // The triangle bound on the library's own check, with a small limit.
  UploadLimits small;
  small.max_surface_triangles = 1000;
  CaseBundle ybif{"y_bifurcation.case", source_file("cases/y_bifurcation.case"), "y_bifurcation.hclm",
                  source_file("cases/y_bifurcation.hclm"), {}, {}};
  const Result<CaseCheck> refused = check_case(ybif, small);
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().status, 413);
  const Result<CaseCheck> accepted = check_case(ybif);
  ASSERT_TRUE(accepted) << accepted.error().message;
  // The bound counts what the subdivision makes: the estimate is the mesh's own count.
  const Result<Ok> exact = [&] {
    UploadLimits at;
    at.max_surface_triangles = accepted.value().mesh_triangles;
    return check_vessel_bounds(ybif.hclm_text, "y_bifurcation.hclm", at);
  }();
  EXPECT_TRUE(exact) << exact.error().message;
  UploadLimits under;
  under.max_surface_triangles = accepted.value().mesh_triangles - 1;
  const Result<Ok> over = check_vessel_bounds(ybif.hclm_text, "y_bifurcation.hclm", under);
  ASSERT_FALSE(over);
  EXPECT_EQ(over.error().message, "y_bifurcation.hclm: its surface would have " + std::to_string(accepted.value().mesh_triangles) +
                                      " triangles or more; the limit is " + std::to_string(under.max_surface_triangles));
}

INSTANTIATE_TEST_SUITE_P(Backends, ForgedRecordsTest, ::testing::ValuesIn(kBackends), BackendName());

}  // namespace
}  // namespace cathbox::server::test
