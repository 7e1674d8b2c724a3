#include "scenario/scenario_runner.hpp"

#include <fstream>
#include <iterator>
#include <sstream>

#include <gtest/gtest.h>

#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"

namespace cathbox::tool {
namespace {

const std::string kData = std::string(CATHBOX_SOURCE_DIR) + "/tests/sim/tool/data/";

struct RunOutput {
  ScenarioResult result;
  std::string csv;
  std::int32_t wire_tip_segment = -1;
};

RunOutput run(const std::string& script_text, std::int64_t every) {
  const CaseParse c = load_case(kData + "y_analytic.case");
  EXPECT_TRUE(c) << c.error().message;
  const ScriptParse s = parse_script(script_text, "test.actions");
  EXPECT_TRUE(s) << (s ? "" : s.error().message);
  WorldBuild world = build_world(*c);
  EXPECT_TRUE(world.ok()) << world.error().message;
  Simulator sim((*world)->wall(), c->tools, (*world)->entry());
  ScenarioOptions options;
  options.every_ms = every;
  options.script_name = "test.actions";
  std::ostringstream csv;
  RunOutput r;
  r.result = run_scenario(sim, *s, options, csv);
  r.csv = csv.str();
  r.wire_tip_segment = sim.tip_segment(sim.find_tool("wire"));
  return r;
}

std::string steer_script() {
  const ScriptParse s = load_script(kData + "y_steer.actions");
  EXPECT_TRUE(s) << (s ? "" : s.error().message);
  std::ifstream in(kData + "y_steer.actions");
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(ScenarioRunner, SameInputsGiveByteIdenticalLogs) {
  const std::string script = steer_script();
  const RunOutput a = run(script, 1);
  const RunOutput b = run(script, 1);
  ASSERT_TRUE(a.result.ok) << a.result.error;
  EXPECT_EQ(a.result.steps, 5000u);
  EXPECT_EQ(a.result.rows, 5000u);
  EXPECT_EQ(a.csv, b.csv);
  EXPECT_EQ(a.csv.rfind("time_ms,tool,insertion_mm,rotation_rad,tip_x_mm,tip_y_mm,tip_z_mm,force_mN,torque_mNmm,contacts,tip_segment\n", 0), 0u);
  // The wire was steered into child 1 and the catheter followed it there.
  EXPECT_EQ(a.wire_tip_segment, 1);
  EXPECT_NE(a.csv.find("\n5000,catheter,70.0000,"), std::string::npos);
}

TEST(ScenarioRunner, EveryLogsASubsetOfTheRows) {
  const std::string script = steer_script();
  const RunOutput all = run(script, 1);
  const RunOutput some = run(script, 250);
  EXPECT_EQ(some.result.rows, 20u);
  // Every logged row also appears, unchanged, in the full log.
  std::istringstream lines(some.csv);
  std::string line;
  std::getline(lines, line);
  while (std::getline(lines, line)) EXPECT_NE(all.csv.find("\n" + line + "\n"), std::string::npos) << line;
}

TEST(ScenarioRunner, WithoutEndRunsUntilMotionsSettle) {
  const RunOutput r = run("0 insert_to 10 at 20\n", 1);
  ASSERT_TRUE(r.result.ok);
  EXPECT_NEAR(static_cast<double>(r.result.steps), 500.0 + 100.0, 1.0);  // 10 mm at 20 mm/s, then 100 ms
}

TEST(ScenarioRunner, UnknownToolIsAFileLineError) {
  const RunOutput r = run("0 insert_to 10\n10 select nope\n", 1);
  EXPECT_FALSE(r.result.ok);
  EXPECT_EQ(r.result.error, "test.actions:2: select: the case has no tool 'nope' (tools: catheter wire)");
  EXPECT_EQ(r.result.steps, 0u);
}

}  // namespace
}  // namespace cathbox::tool
