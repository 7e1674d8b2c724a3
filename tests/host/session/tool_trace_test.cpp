// session::ToolTrace (`cathbox session replay --trace`): a line per tool for every tick of its
// window and none outside it, each giving the tick's hand force and its change since the tick
// before, round the dead-end run's largest change.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>

#include "hand_force_trace.hpp"
#include "session/tool_trace.hpp"

namespace cathbox::session {
namespace {

// Both observers on one run: the trace, and every tool's hand force at every tick.
class Both final : public TickObserver {
 public:
  explicit Both(ToolTrace& trace) : trace_(trace) {}
  void observe(const TickView& v) override {
    trace_.observe(v);
    for (std::size_t t = 0; t < v.sim.tool_count(); ++t) force[{v.time_us / 1000, t}] = v.sim.hand_force_mN(t);
    tools = v.sim.tool_count();
  }
  std::map<std::pair<std::int64_t, std::size_t>, double> force;  // (ms, tool) -> mN
  std::size_t tools = 0;

 private:
  ToolTrace& trace_;
};

TEST(ToolTrace, PrintsEveryToolAtEveryTickOfItsWindowWithTheChangeSinceTheTickBefore) {
  std::FILE* out = std::tmpfile();
  ASSERT_NE(out, nullptr);
  ToolTrace trace(7'640'000, 7'650'000, out);
  Both both(trace);
  Metrics metrics;
  const std::string data = std::string(CATHBOX_SOURCE_DIR) + "/tests/host/session/data/";
  ASSERT_TRUE(test::run_scripted(data + "dead_end.case", data + "dead_end.actions", both, metrics));
  ASSERT_GE(both.tools, 1U);
  EXPECT_EQ(trace.lines(), static_cast<std::int64_t>(11 * both.tools));  // 7.640 ... 7.650 s
  std::rewind(out);
  char line[8192];
  int lines = 0, held = 0, touching = 0;
  double largest = 0.0, largest_s = 0.0;
  while (std::fgets(line, sizeof line, out) != nullptr) {
    ++lines;
    const std::string text(line);
    double s = 0.0, ins = 0.0, f = 0.0, df = 0.0;
    char name[64] = {};
    ASSERT_EQ(std::sscanf(line, "%lf %63s", &s, name), 2) << text;
    const std::size_t at = text.find(" ins ");
    ASSERT_NE(at, std::string::npos) << text;
    ASSERT_EQ(std::sscanf(line + at, " ins %lf F %lf dF %lf", &ins, &f, &df), 3) << text;
    held += text.find(" held ins ") != std::string::npos ? 1 : 0;
    touching += text.find("| wall n") != std::string::npos ? 1 : 0;
    const auto ms = static_cast<std::int64_t>(std::llround(s * 1e3));
    ASSERT_GE(ms, 7640);
    ASSERT_LE(ms, 7650);
    std::size_t tool = both.tools;
    for (std::size_t t = 0; t < both.tools; ++t) {
      if (std::abs(both.force[{ms, t}] - f) <= 0.05 && std::abs(both.force[{ms, t}] - both.force[{ms - 1, t}] - df) <= 0.05) tool = t;
    }
    EXPECT_LT(tool, both.tools) << "no tool had this force and change at this tick: " << text;
    if (std::abs(df) > largest) largest = std::abs(df), largest_s = s;
  }
  std::fclose(out);
  EXPECT_EQ(lines, trace.lines());
  EXPECT_EQ(held, 11) << "one held tool a tick";
  EXPECT_GT(touching, 0) << "the wire is on the dead end's wall";
  // The window's largest change a tick, from the session's forces: the dead-end run's largest
  // (hand_force_jumps_test.cpp prints it: 99.0 mN at 7.647 s on record format 40).
  double expected = 0.0;
  std::int64_t expected_ms = 0;
  for (std::int64_t ms = 7640; ms <= 7650; ++ms) {
    for (std::size_t t = 0; t < both.tools; ++t) {
      const double change = std::abs(both.force[{ms, t}] - both.force[{ms - 1, t}]);
      if (change > expected) expected = change, expected_ms = ms;
    }
  }
  EXPECT_GT(expected, 50.0) << "a window where the hand force moves";
  EXPECT_NEAR(largest, expected, 0.05);
  EXPECT_EQ(std::llround(largest_s * 1e3), expected_ms);
}

}  // namespace
}  // namespace cathbox::session
