// Six tools in one case (issue 29 item 5, balloon-assisted coiling): the balloon remodelling case
// of tests/host/session/data (guide > balloon catheter > its 0.010" wire, guide > microcatheter >
// microwire, microcatheter > coil) as a session in virtual time. Its action script moves every
// tool; the record carries tool 5's moves (bits 10 and 11 of the tools entry's u16 mask) and
// replays with every state hash matching; a seventh tool is refused in one line naming its line.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "session/action_script_hand.hpp"
#include "session/record_reader.hpp"
#include "session/replay.hpp"
#include "session/session.hpp"
#include "session_fixtures.hpp"

namespace cathbox::session {
namespace {

const std::string kData = std::string(CATHBOX_SOURCE_DIR) + "/tests/host/session/data/";

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(SixTools, TheBalloonRemodellingCaseRunsRecordsAndReplays) {
  SessionCaseLoad loaded = load_session_case(kData + "balloon_remodelling.case");
  ASSERT_TRUE(loaded) << loaded.error().message;
  ASSERT_EQ(loaded.value()->spec.tools.size(), 6u);
  auto script = ActionScriptHand::load(kData + "balloon_remodelling.actions", *loaded.value());
  ASSERT_TRUE(script) << script.error().message;
  const std::string path = fixtures::temp_path("session_test", "six_tools.cbxrec");
  Metrics live;
  {
    Session s(std::move(loaded.value()), std::move(*script));
    const base::Status<> recording = s.record_to(path);
    ASSERT_TRUE(recording) << recording.error().message;
    while (!s.over()) s.step_virtual(500);
    EXPECT_EQ(s.end_reason(), record::EndReason::kHandFinished);
    live = s.metrics();
    s.snapshots().acquire();
    EXPECT_EQ(s.snapshots().read_slot().tool_count, 6) << "the snapshot carries every tool";
  }
  ASSERT_EQ(live.convergence.size(), 6u);
  const char* const names[] = {"guide", "balloon", "balloon_wire", "microcatheter", "microwire", "coil"};
  for (std::size_t t = 0; t < 6; ++t) {
    EXPECT_EQ(live.convergence[t].tool, names[t]);
    // Out of their catheters (a free node to solve): all but the coil, still in the microcatheter.
    if (t < 5) {
      EXPECT_GT(live.convergence[t].solved_ticks, 0) << names[t];
    }
  }
  EXPECT_EQ(live.convergence[5].solved_ticks, 0);

  // The record: six tools in its header, each at its scripted end (insertion µm, rotation µrad).
  auto opened = RecordReader::open(path);
  ASSERT_TRUE(opened) << opened.error().message;
  auto reader = std::move(*opened);
  ASSERT_EQ(reader->header().tools.size(), 6u);
  EXPECT_TRUE(reader->header().tools[1].balloon.present());
  TickRecord t;
  TickRecord last;
  while (reader->next(t)) last = t;
  ASSERT_TRUE(reader->error().empty()) << reader->error();
  const std::int64_t insertion_um[] = {25'000, 35'000, 40'000, 35'000, 40'000, 25'000};
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(last.tools[i].insertion_um, insertion_um[i]) << names[i];
  EXPECT_NEAR(static_cast<double>(last.tools[2].rotation_urad), 1.5707963e6, 1.0);   // 90 degrees
  EXPECT_NEAR(static_cast<double>(last.tools[4].rotation_urad), 1.5707963e6, 1.0);
  EXPECT_NEAR(static_cast<double>(last.tools[5].rotation_urad), 0.5235988e6, 1.0);   // 30 degrees

  const ReplayResult r = replay_record(path);
  ASSERT_TRUE(r.error.empty()) << r.error;
  EXPECT_FALSE(r.mismatch);
  EXPECT_GE(r.hashes_checked, 29);
  ASSERT_EQ(r.metrics.convergence.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(r.metrics.convergence[i].solved_ticks, live.convergence[i].solved_ticks) << names[i];
    EXPECT_EQ(r.metrics.convergence[i].unconverged_ticks, live.convergence[i].unconverged_ticks) << names[i];
  }
  EXPECT_DOUBLE_EQ(r.metrics.tip_path_mm, live.tip_path_mm);
}

TEST(SixTools, ASeventhToolIsRefusedInOneLineNamingItsLine) {
  std::string text = read_text(kData + "balloon_remodelling.case");
  ASSERT_FALSE(text.empty());
  const std::size_t lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
  text += "\ntool second_wire guidewire\n  section 1800 od=0.36 ei=40 gj=31\n  inside microcatheter\nend\n";
  const std::string relative = "vessel ../../../../cases/";
  const std::size_t vessel = text.find(relative);
  ASSERT_NE(vessel, std::string::npos);
  text.replace(vessel, relative.size(), "vessel " + std::string(CATHBOX_SOURCE_DIR) + "/cases/");
  const std::string path = fixtures::temp_path("session_test", "seven_tools.case");
  {
    std::ofstream(path) << text;
  }
  const SessionCaseLoad loaded = load_session_case(path);
  ASSERT_FALSE(loaded);
  EXPECT_EQ(loaded.error().message, path + ":" + std::to_string(lines + 2) + ": too many tools (at most 6)");
}

}  // namespace
}  // namespace cathbox::session
