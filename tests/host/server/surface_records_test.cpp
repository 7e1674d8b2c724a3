// Results of `surface FILE` cases: the instructor uploads the case with its own wall (CBXMESH2
// bytes), the server stores them in the case's bundle, and a trainee's record of that case is
// accepted only when it replays exactly and carries the very same surface bytes; a record made on
// another wall (here: the same vessel meshed one level finer) is refused naming header field
// 'surface_bytes'.
#include <filesystem>
#include <fstream>

#include "record_files.hpp"
#include "scenario/case_file.hpp"
#include "session/action_script_hand.hpp"
#include "session/session.hpp"
#include "support/api_fixture.hpp"
#include "vessel/hclm.hpp"
#include "vessel/mesh_wire.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::server::test {
namespace {

using nlohmann::json;

// A folder holding the y-bifurcation as a surface case: its HCLM, its lumen meshed at
// `subdivision_level` as lumen.cbxmesh, and ysurf.case naming both. The case file's path.
std::string write_surface_case(const std::string& folder, int subdivision_level) {
  const std::filesystem::path dir = scratch(folder);
  std::filesystem::create_directories(dir);
  const std::string hclm = read_all(std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation.hclm");
  std::ofstream(dir / "y_bifurcation.hclm", std::ios::binary) << hclm;
  const vessel::HclmReadResult model = vessel::read_hclm(hclm, "y_bifurcation.hclm");
  EXPECT_TRUE(model.ok());
  vessel::MeshOptions options;
  options.subdivision_level = subdivision_level;
  const vessel::VesselSurface lumen = vessel::build_vessel_surface(model.model, options);
  EXPECT_TRUE(lumen.ok()) << lumen.error;
  std::ofstream(dir / "lumen.cbxmesh", std::ios::binary) << vessel::encode_mesh_wire(lumen.mesh);
  const std::string case_text = read_all(std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation.case");
  std::ofstream(dir / "ysurf.case", std::ios::binary) << case_text << "surface lumen.cbxmesh\n";
  return (dir / "ysurf.case").string();
}

// The left branch by action script on that case, recorded in virtual time: the record's bytes.
std::string record_surface_case(const std::string& case_path) {
  const auto scene = session::load_session_case(case_path);
  EXPECT_TRUE(scene && scene.value()->surface_given()) << (scene ? "no surface" : scene.error().message);
  return record_by_script(case_path, std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation_left.actions");
}

ApiResponse upload_surface_case(ApiFixture& f, const std::string& case_path, const std::string& token) {
  const std::filesystem::path dir = std::filesystem::path(case_path).parent_path();
  const json body = {{"name", "ysurf"},
                     {"case_file", "ysurf.case"},
                     {"case", read_all(case_path)},
                     {"hclm_file", "y_bifurcation.hclm"},
                     {"hclm", read_all((dir / "y_bifurcation.hclm").string())},
                     {"surface_file", "lumen.cbxmesh"},
                     {"surface_hex", hex_of(read_all((dir / "lumen.cbxmesh").string()))}};
  return f.call("POST", "/api/v1/cases", body.dump(), token);
}

class SurfaceRecordsTest : public ::testing::TestWithParam<std::string> {};

TEST_P(SurfaceRecordsTest, TheRecordMustCarryTheAssignedSurface) {
  ApiFixture f(GetParam(), make_session_checker());
  const std::string teacher = f.user("teacher", Role::kInstructor);
  const std::string alice = f.user("alice", Role::kTrainee);
  const std::string assigned = write_surface_case("surface_assigned", 1);
  const ApiResponse up = upload_surface_case(f, assigned, teacher);
  ASSERT_EQ(up.status, 201) << up.body;
  // The download is the bundle with the surface's bytes (hex), so a trainer runs the same wall.
  const json a = f.call_json("POST", "/api/v1/assignments", {{"trainee", "alice"}, {"case", "ysurf"}}, teacher, 201);
  const std::string target = "/api/v1/results?assignment=" + std::to_string(a["id"].get<int>());

  const ApiResponse stored = f.call("POST", target, record_surface_case(assigned), alice);
  ASSERT_EQ(stored.status, 201) << stored.body;
  EXPECT_EQ(json::parse(stored.body)["case"], "ysurf");

  const ApiResponse other = f.call("POST", target, record_surface_case(write_surface_case("surface_other", 2)), alice);
  EXPECT_EQ(other.status, 422);
  EXPECT_EQ(error_of(other), "record: header field 'surface_bytes' (lumen.cbxmesh) is not the assignment's case 'ysurf' version 1 (by content hash)");
}

TEST_P(SurfaceRecordsTest, ASurfaceCaseIsRefusedWithoutItsSurface) {
  ApiFixture f(GetParam(), make_session_checker());
  const std::string teacher = f.user("teacher", Role::kInstructor);
  const std::string path = write_surface_case("surface_missing", 1);
  const json body = {{"name", "ysurf"}, {"case_file", "ysurf.case"}, {"case", read_all(path)}, {"hclm_file", "y_bifurcation.hclm"},
                     {"hclm", read_all(std::string(CATHBOX_SOURCE_DIR) + "/cases/y_bifurcation.hclm")}};
  const ApiResponse up = f.call("POST", "/api/v1/cases", body.dump(), teacher);
  EXPECT_EQ(up.status, 422);
  EXPECT_EQ(error_of(up), "ysurf.case:15: the case names surface 'lumen.cbxmesh': upload it as surface_file/surface_hex");
  json bad_hex = body;
  bad_hex["surface_file"] = "lumen.cbxmesh";
  bad_hex["surface_hex"] = "4x";
  EXPECT_EQ(error_of(f.call("POST", "/api/v1/cases", bad_hex.dump(), teacher)), "field 'surface_hex': not lowercase hex of whole bytes");
  json garbage = bad_hex;
  garbage["surface_hex"] = hex_of("not a mesh");
  const ApiResponse refused = f.call("POST", "/api/v1/cases", garbage.dump(), teacher);
  EXPECT_EQ(refused.status, 422);
  EXPECT_NE(error_of(refused).find("lumen.cbxmesh"), std::string::npos) << error_of(refused);
}

INSTANTIATE_TEST_SUITE_P(Backends, SurfaceRecordsTest, ::testing::ValuesIn(kBackends), BackendName());

}  // namespace
}  // namespace cathbox::server::test
