// `cathbox session replay --check` on a complete record whose inputs no longer give the recorded
// states: exit 1 and one line, the first differing tick (no tick counts, no "no end block" line:
// the replay stopped there on purpose, the record is not cut).
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "record_tamper.hpp"

namespace {

const std::string kBin = std::string(CATHBOX_BINARY_DIR) + "/bin/cathbox";
const std::string kCases = std::string(CATHBOX_SOURCE_DIR) + "/cases/";
const std::string kTmp = std::string(CATHBOX_BINARY_DIR) + "/tests/host/cli/";

int run(const std::string& args, const std::string& out_file) {
  const int status = std::system((kBin + " " + args + " >" + out_file + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(CathboxSessionReplay, CheckStoppedAtAMismatchPrintsOnlyTheMismatch) {
  const std::string script = kTmp + "replay_check.actions";
  std::ofstream(script) << "0 select guidewire\n0 insert_to 30 at 30\n1000 end\n";
  const std::string rec = kTmp + "replay_check.cbxrec";
  ASSERT_EQ(run("session run --case " + kCases + "y_bifurcation.case --script " + script + " --record " + rec,
                kTmp + "replay_check_run.out"),
            0)
      << slurp(kTmp + "replay_check_run.out");
  // The untouched record replays, and reports its tick counts.
  ASSERT_EQ(run("session replay " + rec + " --check", kTmp + "replay_check_ok.out"), 0);
  const std::string ok = slurp(kTmp + "replay_check_ok.out");
  EXPECT_NE(ok.find("replayed 1000 of 1000 recorded ticks"), std::string::npos) << ok;
  EXPECT_NE(ok.find("every state hash matches"), std::string::npos) << ok;
  // Inputs changed by 1 um from tick 500: the hash at tick 599 is the first to differ.
  const std::string tampered = kTmp + "replay_check_tampered.cbxrec";
  cathbox::session::testing::tamper_record(rec, tampered, 500);
  ASSERT_EQ(run("session replay " + tampered + " --check", kTmp + "replay_check_bad.out"), 1);
  const std::string bad = slurp(kTmp + "replay_check_bad.out");
  EXPECT_EQ(bad.rfind("state hash differs at tick 599 (0.600 s): recorded ", 0), 0U) << bad;
  EXPECT_EQ(bad.find('\n'), bad.size() - 1) << "more than one line: " << bad;
  // Without --check the replay runs to the end block and says so with its counts.
  ASSERT_EQ(run("session replay " + tampered, kTmp + "replay_check_all.out"), 0);
  const std::string all = slurp(kTmp + "replay_check_all.out");
  EXPECT_NE(all.find("replayed 1000 of 1000 recorded ticks"), std::string::npos) << all;
  EXPECT_NE(all.find("state hash differs at tick 599"), std::string::npos) << all;
  EXPECT_EQ(all.find("no end block"), std::string::npos) << all;
}

}  // namespace
