// A six-tool record (issue 29 item 5, balloon-assisted coiling): the instructor uploads the
// balloon remodelling case of tests/host/session/data with its vessel, a trainee's record of its
// action script (all six tools moving, tool 5 on bits 10 and 11 of the tools entry's mask) is
// replayed by the server's checker and stored with each of the six tools' metric
// (`unconverged_pct.TOOL`).
#include <filesystem>
#include <fstream>
#include <string>

#include "record_files.hpp"
#include "support/api_fixture.hpp"

namespace cathbox::server::test {
namespace {

using nlohmann::json;

const std::string kData = std::string(CATHBOX_SOURCE_DIR) + "/tests/host/session/data/";

// The case in a folder of its own beside its vessel (the upload names the vessel by file name).
std::string write_case() {
  const std::filesystem::path dir = scratch("six_tools");
  std::filesystem::create_directories(dir);
  std::string text = read_all(kData + "balloon_remodelling.case");
  const std::string relative = "vessel ../../../../cases/";
  const std::size_t at = text.find(relative);
  EXPECT_NE(at, std::string::npos);
  if (at != std::string::npos) text.replace(at, relative.size(), "vessel ");
  std::ofstream(dir / "six.case", std::ios::binary) << text;
  std::ofstream(dir / "neuro_small_aneurysm.hclm", std::ios::binary)
      << read_all(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro_small_aneurysm.hclm");
  return (dir / "six.case").string();
}

class SixToolsRecordsTest : public ::testing::TestWithParam<std::string> {};

TEST_P(SixToolsRecordsTest, ASixToolRecordIsReplayedAndStored) {
  ApiFixture f(GetParam(), make_session_checker());
  const std::string teacher = f.user("teacher", Role::kInstructor);
  const std::string alice = f.user("alice", Role::kTrainee);
  const std::string case_path = write_case();
  const std::filesystem::path dir = std::filesystem::path(case_path).parent_path();
  const json body = {{"name", "six"},
                     {"case_file", "six.case"},
                     {"case", read_all(case_path)},
                     {"hclm_file", "neuro_small_aneurysm.hclm"},
                     {"hclm", read_all((dir / "neuro_small_aneurysm.hclm").string())}};
  const ApiResponse up = f.call("POST", "/api/v1/cases", body.dump(), teacher);
  ASSERT_EQ(up.status, 201) << up.body;
  const json a = f.call_json("POST", "/api/v1/assignments", {{"trainee", "alice"}, {"case", "six"}}, teacher, 201);
  const std::string record = record_by_script(case_path, kData + "balloon_remodelling.actions");
  ASSERT_FALSE(record.empty());
  const ApiResponse stored = f.call("POST", "/api/v1/results?assignment=" + std::to_string(a["id"].get<int>()), record, alice);
  ASSERT_EQ(stored.status, 201) << stored.body;
  const json r = json::parse(stored.body);
  EXPECT_EQ(r["case"], "six");
  const json detail = f.call_json("GET", "/api/v1/results/" + std::to_string(r["id"].get<int>()), nullptr, teacher, 200);
  const json& metrics = detail["metrics"];
  ASSERT_TRUE(metrics.is_object()) << detail.dump();
  for (const char* name : {"guide", "balloon", "balloon_wire", "microcatheter", "microwire", "coil"}) {
    EXPECT_TRUE(metrics.contains(std::string("unconverged_pct.") + name)) << name << ": " << metrics.dump();
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, SixToolsRecordsTest, ::testing::ValuesIn(kBackends), BackendName());

}  // namespace
}  // namespace cathbox::server::test
