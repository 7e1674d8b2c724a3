// Results with real session records: the server's record checker replays each upload through
// host/session. A record made by an action script on the bundled y-bifurcation is accepted and
// indexed with the metrics its replay measured; the same bytes again are the same result; a
// record whose inputs were changed by 1 um from tick 3000 is refused at the first hash after the
// change; a cut or foreign record is refused with the reader's line.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "session/action_script_hand.hpp"
#include "vessel/mesh_wire.hpp"
#include "vessel/vessel_mesher.hpp"
#include "session/session.hpp"
#include "support/api_fixture.hpp"
#include "../session/stent_tube_case.hpp"
#include "flow/reperfusion.hpp"
#include "record_files.hpp"
#include "record_tamper.hpp"

namespace cathbox::server::test {
namespace {

using nlohmann::json;

// The record rewritten with the held tool's insertion 1 um further from `from_tick` on.
std::string tampered(const std::string& path, std::int64_t from_tick) {
  const std::string out_path = scratch("tampered.cbxrec");
  session::testing::tamper_record(path, out_path, from_tick);
  return read_all(out_path);
}

class RecordsTest : public ::testing::TestWithParam<std::string> {};

TEST_P(RecordsTest, RealRecordsAreReplayedBeforeTheyCount) {
  ApiFixture f(GetParam(), make_session_checker());
  const std::string teacher = f.user("teacher", Role::kInstructor);
  const std::string alice = f.user("alice", Role::kTrainee);
  ASSERT_EQ(f.upload_bundled_case("y_bifurcation", "ybif", teacher).status, 201);
  const json a = f.call_json("POST", "/api/v1/assignments",
                             {{"trainee", "alice"}, {"case", "ybif"},
                              {"criteria", json::array({{{"metric", "peak_wall_force_mN"}, {"op", "<="}, {"value", 200}},
                                                        {{"metric", "tip_path_mm"}, {"op", ">="}, {"value", 50}}})}},
                             teacher, 201);
  const std::string target = "/api/v1/results?assignment=" + std::to_string(a["id"].get<int>());
  const std::string path = record_left_branch();
  const std::string good = read_all(path);
  const ApiResponse stored = f.call("POST", target, good, alice);
  ASSERT_EQ(stored.status, 201) << stored.body;
  const json r = json::parse(stored.body);
  EXPECT_EQ(r["case"], "ybif");
  EXPECT_EQ(r["passed"], true);
  const json detail = f.call_json("GET", "/api/v1/results/" + std::to_string(r["id"].get<int>()), nullptr, teacher, 200);
  EXPECT_GT(detail["evaluation"]["criteria"][1]["actual"].get<double>(), 50.0);
  EXPECT_EQ(f.call("POST", target, good, alice).status, 200);  // the same bytes: the same result
  EXPECT_EQ(f.call("POST", "/api/v1/results", good, alice).status, 200);  // without an assignment: the same
  // ... but not a second time for another assignment.
  const json b = f.call_json("POST", "/api/v1/assignments", {{"trainee", "alice"}, {"case", "ybif"}}, teacher, 201);
  const ApiResponse other = f.call("POST", "/api/v1/results?assignment=" + std::to_string(b["id"].get<int>()), good, alice);
  EXPECT_EQ(other.status, 409);
  EXPECT_EQ(error_of(other), "record: already stored as result " + std::to_string(r["id"].get<int>()) + " for assignment " +
                                 std::to_string(a["id"].get<int>()) + "; a run counts for one assignment");

  const ApiResponse changed = f.call("POST", target, tampered(path, 3000), alice);
  EXPECT_EQ(changed.status, 422);
  EXPECT_EQ(error_of(changed), "record: tick 3099: state hash differs (tampered or broken)");
  const ApiResponse cut = f.call("POST", target, good.substr(0, 40), alice);
  EXPECT_EQ(cut.status, 422);
  EXPECT_EQ(error_of(cut).rfind("record: byte ", 0), 0U) << error_of(cut);
  const ApiResponse foreign = f.call("POST", target, "not a record", alice);
  EXPECT_EQ(foreign.status, 422);
  EXPECT_EQ(error_of(foreign), "record: byte 12: not a cathbox record: 12 bytes, shorter than the 16-byte file header");
}

std::string header(const ApiResponse& r, const std::string& name) {
  for (const auto& [k, v] : r.headers) {
    if (k == name) return v;
  }
  return {};
}

// The debrief's trace: the record replayed and sampled every 50 ms, the events the metrics
// counted, the result and its evaluation; made by the replay that checked the upload (so even
// the first request is served from the cache), the same as a replay of its own. Same visibility
// as the result. And the browser's mesh of the case (CBXMESH1), coarser than the trainer's.
TEST_P(RecordsTest, DebriefTraceAndBrowserMesh) {
  ApiFixture f(GetParam(), make_session_checker());
  const std::string teacher = f.user("teacher", Role::kInstructor);
  const std::string alice = f.user("alice", Role::kTrainee);
  const std::string bob = f.user("bob", Role::kTrainee);
  const ApiResponse up = f.upload_bundled_case("y_bifurcation", "ybif", teacher);
  ASSERT_EQ(up.status, 201);
  const std::string bytes = read_all(record_left_branch());
  const ApiResponse stored = f.call("POST", "/api/v1/results", bytes, alice);
  ASSERT_EQ(stored.status, 201) << stored.body;
  const json r = json::parse(stored.body);
  const std::string url = "/api/v1/results/" + std::to_string(r["id"].get<int>()) + "/trace";

  const ApiResponse first = f.call("GET", url, "", teacher);
  ASSERT_EQ(first.status, 200) << first.body;
  EXPECT_EQ(header(first, "X-Cathbox-Trace").rfind("cached; ", 0), 0U) << header(first, "X-Cathbox-Trace");
  const json d = json::parse(first.body);
  EXPECT_EQ(d["mesh_url"], "/api/v1/cases/ybif/versions/1/mesh");
  EXPECT_EQ(d["result"]["id"], r["id"]);
  const json& t = d["trace"];
  EXPECT_EQ(t["format"], "cathbox-trace 2");
  EXPECT_FALSE(t.contains("retrieval_mN")) << "not a thrombectomy case";
  EXPECT_EQ(t["period_ms"], 50.0);
  const std::size_t n = t["samples"].get<std::size_t>();
  EXPECT_NEAR(static_cast<double>(n), r["duration_s"].get<double>() * 20.0, 2.0);
  EXPECT_EQ(t["t_ms"].size(), n);
  EXPECT_EQ(t["tip_mm"].size(), 3 * n);
  for (const char* column : {"insertion_mm", "rotation_deg", "hand_mN", "wall_peak_mN", "fluoro", "nodes_mm"}) {
    EXPECT_EQ(t[column].size(), n) << column;
  }
  for (const json& nodes : t["nodes_mm"]) {
    EXPECT_EQ(nodes.size() % 3, 0U);
    EXPECT_LE(nodes.size(), 24U * 3U);
  }
  // The script inserts to 95 mm: the trace's insertion gets there, time only grows.
  EXPECT_NEAR(t["insertion_mm"].back().get<double>(), 95.0, 1.0);
  EXPECT_TRUE(std::is_sorted(t["t_ms"].begin(), t["t_ms"].end()));
  int contacts = 0;
  for (const json& e : t["events"]) contacts += e["kind"] == "wall_contact" ? 1 : 0;
  EXPECT_EQ(contacts, r["metrics"]["wall_contacts"].get<double>());
  EXPECT_EQ(t["target_mm"].size(), 3U);

  const Result<std::string> replayed = make_session_checker()->trace(bytes);
  ASSERT_TRUE(replayed) << replayed.error().message;
  EXPECT_EQ(json::parse(replayed.value()), t);  // deterministic: a replay of its own gives the same
  const ApiResponse again = f.call("GET", url, "", alice);
  ASSERT_EQ(again.status, 200);
  EXPECT_EQ(json::parse(again.body)["trace"], t);
  EXPECT_EQ(f.call("GET", url, "", bob).status, 404);
  EXPECT_EQ(f.call("GET", url, "").status, 401);
  EXPECT_EQ(f.call("GET", "/api/v1/results/999/trace", "", teacher).status, 404);

  const ApiResponse mesh = f.call("GET", "/api/v1/cases/ybif/versions/latest/mesh", "", alice);
  ASSERT_EQ(mesh.status, 200) << mesh.body;
  EXPECT_EQ(mesh.content_type, "application/octet-stream");
  ASSERT_GE(mesh.body.size(), 16U);
  EXPECT_EQ(mesh.body.substr(0, 8), "CBXMESH1");
  std::uint32_t vertices = 0, triangles = 0;
  std::memcpy(&vertices, mesh.body.data() + 8, 4);
  std::memcpy(&triangles, mesh.body.data() + 12, 4);
  EXPECT_GT(triangles, 100U);
  EXPECT_LT(triangles, json::parse(up.body)["sizes"]["mesh_triangles"].get<std::uint32_t>());
  ASSERT_EQ(mesh.body.size(), 16U + 24U * vertices + 12U * triangles);
  std::uint32_t largest = 0;
  for (std::uint32_t i = 0; i < 3 * triangles; ++i) {
    std::uint32_t index = 0;
    std::memcpy(&index, mesh.body.data() + 16 + 24 * vertices + 4 * i, 4);
    largest = std::max(largest, index);
  }
  EXPECT_EQ(largest + 1, vertices);
  EXPECT_EQ(f.call("GET", "/api/v1/cases/ybif/versions/1/mesh", "", teacher).body, mesh.body);
  EXPECT_EQ(f.call("GET", "/api/v1/cases/ybif/versions/2/mesh", "", teacher).status, 404);
  EXPECT_EQ(f.call("GET", "/api/v1/cases/ybif/versions/1/mesh", "").status, 401);

  // ?level=collision: the very surface a native session builds its collision tree on.
  const ApiResponse exact = f.call("GET", "/api/v1/cases/ybif/versions/1/mesh?level=collision", "", alice);
  ASSERT_EQ(exact.status, 200) << exact.body;
  EXPECT_NE(header(exact, "ETag"), header(mesh, "ETag"));
  const auto decoded = cathbox::vessel::decode_mesh_wire(
      std::span(reinterpret_cast<const std::uint8_t*>(exact.body.data()), exact.body.size()));
  ASSERT_TRUE(decoded) << decoded.error().message;
  const cathbox::vessel::VesselSurface native =
      cathbox::vessel::load_vessel_surface(std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation.hclm");
  ASSERT_TRUE(native.ok()) << native.error;
  EXPECT_EQ(decoded.value().positions_mm, native.mesh.positions_mm);
  EXPECT_EQ(decoded.value().normals, native.mesh.normals);
  EXPECT_EQ(decoded.value().triangles, native.mesh.triangles);
  EXPECT_EQ(decoded.value().triangle_regions, native.mesh.triangle_regions);
  EXPECT_EQ(f.call("GET", "/api/v1/cases/ybif/versions/1/mesh?level=fine", "", alice).status, 400);
}

// The cache of meshes and traces: least recently used out first; with a folder, a second
// cache (a restarted server) finds what the first built without building it again.
// One injection is one event on the debrief's time line: the contrast volume grows with each
// 10 ms transport step, and the trace once marked each of those steps (2 mL at 2 mL/s: ~100
// marks). A catheter in the y-bifurcation's parent, one injection, recorded and traced.
TEST(DebriefTrace, OneInjectionIsOneEvent) {
  const std::string source = std::string(CATHBOX_SOURCE_DIR) + "/cases/";
  std::filesystem::copy_file(source + "y_bifurcation.hclm", scratch("y_bifurcation.hclm"),
                             std::filesystem::copy_options::overwrite_existing);
  std::ofstream(scratch("inject.case")) << "cathbox-case 1\nname Y bifurcation: one injection\nvessel y_bifurcation.hclm\n"
                                           "tool catheter catheter\n  section 1000 od=1.67 ei=250 gj=190\n"
                                           "  friction 0.15\n  inner_diameter 1.0\nend\n";
  std::ofstream(scratch("inject.actions")) << "0 select catheter\n0 insert_to 30 at 30\n1000 fluoro on\n"
                                              "1000 inject 2 at 2\n2500 fluoro off\n2600 end\n";
  auto scene = session::load_session_case(scratch("inject.case"));
  ASSERT_TRUE(scene) << scene.error().message;
  auto script = session::ActionScriptHand::load(scratch("inject.actions"), *scene.value());
  ASSERT_TRUE(script) << script.error().message;
  const std::string path = scratch("inject.cbxrec");
  {
    session::Session s(std::move(scene.value()), std::move(*script));
    ASSERT_TRUE(s.record_to(path));
    while (!s.over()) s.step_virtual(1000);
    ASSERT_TRUE(s.recorder()->close());
    ASSERT_NEAR(s.metrics().contrast_volume_ml.value_or(0.0), 2.0, 1e-6);  // the injection was made, all of it
  }
  const Result<std::string> traced = make_session_checker()->trace(read_all(path));
  ASSERT_TRUE(traced) << traced.error().message;
  const json trace = json::parse(traced.value());
  std::vector<double> injections_ms;
  for (const json& e : trace["events"]) {
    if (e["kind"] == "injection") injections_ms.push_back(e["t_ms"].get<double>());
  }
  ASSERT_EQ(injections_ms.size(), 1U) << trace["events"].dump();
  EXPECT_NEAR(injections_ms[0], 1000.0, 1.0);  // at the script's tick
}

// The stent retriever in the small Y (tests/host/session/stent_tube_case.hpp) driven by
// `script`, recorded to `name` in virtual time and traced; the session's metrics in `m`.
json traced_stent_tube(const char* script_text, const std::string& name, session::Metrics& m) {
  const std::string case_path = session::fixtures::write_stent_tube_case("clot 2 6 10 red=60 fibrin=30\n", "",
                                                                          "server_records_test." + std::to_string(::getpid()));
  auto scene = session::load_session_case(case_path);
  EXPECT_TRUE(scene) << scene.error().message;
  if (!scene) return {};
  std::unique_ptr<session::Hand> script = session::fixtures::script_hand(*scene.value(), script_text);
  EXPECT_TRUE(script);
  if (!script) return {};
  const std::string path = scratch(name);
  {
    session::Session s(std::move(scene.value()), std::move(script));
    EXPECT_TRUE(s.record_to(path));
    while (!s.over()) s.step_virtual(1000);
    EXPECT_TRUE(s.recorder()->close());
    m = s.metrics();
  }
  const Result<std::string> traced = make_session_checker()->trace(read_all(path));
  EXPECT_TRUE(traced) << traced.error().message;
  return traced ? json::parse(traced.value()) : json{};
}

// The trace's events of `kind`, in order.
std::vector<json> events_of(const json& trace, const char* kind) {
  std::vector<json> out;
  for (const json& e : trace["events"]) {
    if (e["kind"] == kind) out.push_back(e);
  }
  return out;
}

// A thrombectomy on the debrief's plot: the stent retriever's one pass in the small Y
// (tests/host/session/stent_tube_case.hpp) recorded and traced. Each pass is a `pass` mark
// with the eTICI the metrics give it; the retrieval force is a series whose peak is the session's
// retrieval_force_peak_N (the same pull, converged steps only; to 0.01 mN), reached while the
// stent was being pulled back, before the pass's mark.
TEST(DebriefTrace, StentPassesAndRetrievalForceAreOnThePlot) {
  session::Metrics m;
  const json t = traced_stent_tube(session::fixtures::kStentTubeScript, "stent.cbxrec", m);
  ASSERT_TRUE(m.thrombectomy);
  const session::ThrombectomyFigures& f = *m.thrombectomy;
  ASSERT_EQ(f.stent_passes, 1);
  ASSERT_GT(f.retrieval_force_peak_N, 0.2);  // as stent_retriever_tube_test.cpp measures it
  ASSERT_TRUE(t.contains("events"));
  const std::vector<json> passes = events_of(t, "pass");
  ASSERT_EQ(passes.size(), static_cast<std::size_t>(f.passes)) << t["events"].dump();
  EXPECT_EQ(passes[0]["pass"], 1);
  EXPECT_EQ(passes[0]["etici"], std::string(flow::etici_label(f.etici_after_pass[0])));
  EXPECT_EQ(passes[0]["etici"], "3");
  EXPECT_NEAR(passes[0]["reperfused_pct"].get<double>(), f.reperfused_pct_after_pass[0], 0.01);
  EXPECT_GT(passes[0]["t_ms"].get<double>(), 4900.0) << "the pass ends after the pull began";
  const json& pull = t["retrieval_mN"];
  ASSERT_EQ(pull.size(), t["samples"].get<std::size_t>());
  std::size_t at = 0;
  for (std::size_t i = 0; i < pull.size(); ++i) {
    if (pull[i].get<double>() > pull[at].get<double>()) at = i;
  }
  EXPECT_NEAR(pull[at].get<double>(), 1000.0 * f.retrieval_force_peak_N, 0.005);
  const double peak_ms = t["t_ms"][at].get<double>();
  std::printf("stent pass: %s; retrieval peak %.2f mN at %.0f ms (metrics %.5f N)\n", passes[0].dump().c_str(),
              pull[at].get<double>(), peak_ms, f.retrieval_force_peak_N);
  EXPECT_GT(peak_ms, 4900.0);
  EXPECT_LE(peak_ms, passes[0]["t_ms"].get<double>() + t["period_ms"].get<double>());
  EXPECT_EQ(pull[0], 0.0) << "no pull before the stent is retrieved";
}

// The careless contrast in the same Y (issue 30): no flow arrest, the microcatheter left where it
// unsheathed the stent (in the parent, 26 mm from the entry) and the stent pulled fast straight
// into it. The stent holds the clot and the microcatheter's tip strips it off into the flow, which
// carries it downstream until it lodges (measured: one embolus, in the straight branch, ~0.45 s
// after the pass, not a new territory; ~6 s of CPU). Each lodged embolus is an `embolus` mark
// after the pass that shed it, numbered from 1, with the segment and the new-territory flag the
// metrics give it.
constexpr const char* kCarelessStentTubeScript =
    "0 select guide\n0 insert_to 20 at 40\n"
    "0 select microcatheter\n0 insert_to 56 at 40\n"
    "1500 select stent\n1500 insert_to 50 at 50\n"
    "2500 select microcatheter\n2500 insert_by -30 at 20\n"
    "4600 select stent\n4600 insert_to 10 at 20\n"
    "6900 end\n";

TEST(DebriefTrace, ALodgedEmbolusIsAnEventOnThePlot) {
  session::Metrics m;
  const json t = traced_stent_tube(kCarelessStentTubeScript, "careless.cbxrec", m);
  ASSERT_TRUE(m.thrombectomy);
  const session::ThrombectomyFigures& f = *m.thrombectomy;
  std::printf("careless tube: %d pass(es), %d emboli (%d new territory)", f.passes, f.emboli, f.emboli_new_territory);
  for (const std::string& name : f.emboli_lodged) std::printf(", %s", name.c_str());
  std::printf("\n");
  ASSERT_EQ(f.passes, 1);
  ASSERT_GE(f.emboli, 1) << "the careless pass sheds a fragment that lodges";
  ASSERT_EQ(f.emboli_lodged.size(), static_cast<std::size_t>(f.emboli));
  const std::vector<json> passes = events_of(t, "pass");
  const std::vector<json> emboli = events_of(t, "embolus");
  ASSERT_EQ(passes.size(), 1U) << t["events"].dump();
  ASSERT_EQ(emboli.size(), static_cast<std::size_t>(f.emboli)) << t["events"].dump();
  int new_territory = 0;
  for (std::size_t k = 0; k < emboli.size(); ++k) {
    const json& e = emboli[k];
    EXPECT_EQ(e["embolus"], static_cast<int>(k) + 1);
    EXPECT_EQ(e["segment"], f.emboli_lodged[k]);
    ASSERT_TRUE(e.contains("new_territory")) << e.dump();
    new_territory += e["new_territory"].get<bool>() ? 1 : 0;
    EXPECT_GT(e["t_ms"].get<double>(), passes[0]["t_ms"].get<double>()) << "a fragment lodges after the pass that shed it";
    if (k > 0) {
      EXPECT_GE(e["t_ms"].get<double>(), emboli[k - 1]["t_ms"].get<double>());
    }
  }
  EXPECT_EQ(new_territory, f.emboli_new_territory);
}

TEST(ArtifactCache, EvictsTheLeastRecentlyUsedAndKeepsValuesOnDisk) {
  ArtifactCache small(10);
  const auto value = [](std::string v) { return [v]() -> Result<std::string> { return v; }; };
  const auto never = []() -> Result<std::string> { return make_error(500, "built again"); };
  bool hit = true;
  ASSERT_EQ(*small.get_or_build("a", value("12345"), &hit).value(), "12345");
  EXPECT_FALSE(hit);
  ASSERT_TRUE(small.get_or_build("b", value("6789"), &hit));
  ASSERT_TRUE(small.get_or_build("a", never, &hit));  // a used last: b leaves for c
  EXPECT_TRUE(hit);
  ASSERT_TRUE(small.get_or_build("c", value("xy"), &hit));
  EXPECT_EQ(small.bytes(), 7U);
  EXPECT_FALSE(small.get_or_build("b", never, &hit));
  EXPECT_EQ(small.get_or_build("x", []() -> Result<std::string> { return make_error(422, "refused"); }).error().message, "refused");

  const std::string folder = scratch("artifacts");
  std::filesystem::remove_all(folder);
  {
    ArtifactCache first;
    first.keep_on_disk(folder);
    first.put("trace1:abc", std::string(100000, 't'), first.erasures());
  }
  ArtifactCache second;
  second.keep_on_disk(folder);
  const Result<std::shared_ptr<const std::string>> again = second.get_or_build("trace1:abc", never, &hit);
  ASSERT_TRUE(again) << again.error().message;
  EXPECT_TRUE(hit);
  EXPECT_EQ(*again.value(), std::string(100000, 't'));
  EXPECT_LT(std::filesystem::file_size(std::filesystem::path(folder) / "trace1-abc.zst"), 1000U);
}

// A value built while a key is erased (a trace replayed from a record read just before its
// trainee was deleted) is answered but kept neither in memory nor on disk; so is a put whose
// source was stored before an erase.
TEST(ArtifactCache, KeepsNothingBuiltAcrossAnErase) {
  const std::string folder = scratch("artifacts-erase");
  std::filesystem::remove_all(folder);
  ArtifactCache cache;
  cache.keep_on_disk(folder);
  const auto erasing = [&]() -> Result<std::string> {
    cache.erase("trace1:theirs");  // the delete lands while this replay runs
    return std::string("built from a deleted record");
  };
  bool hit = true;
  const Result<std::shared_ptr<const std::string>> built = cache.get_or_build("trace1:theirs", erasing, &hit);
  ASSERT_TRUE(built);
  EXPECT_EQ(*built.value(), "built from a deleted record");
  EXPECT_EQ(cache.bytes(), 0U);
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::path(folder) / "trace1-theirs.zst"));
  const std::uint64_t before = cache.erasures();
  cache.erase("trace1:other");
  cache.put("trace1:late", "an upload's trace", before);
  EXPECT_EQ(cache.bytes(), 0U);
  cache.put("trace1:late", "an upload's trace", cache.erasures());
  EXPECT_EQ(cache.bytes(), 17U);
}

INSTANTIATE_TEST_SUITE_P(Backends, RecordsTest, ::testing::ValuesIn(kBackends), BackendName());

}  // namespace
}  // namespace cathbox::server::test
