// `cathbox sim run` end to end: exit codes, file:line errors, byte-identical logs.
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

namespace {

const std::string kBin = std::string(CATHBOX_BINARY_DIR) + "/bin/cathbox";
const std::string kData = std::string(CATHBOX_SOURCE_DIR) + "/tests/sim/tool/data/";
const std::string kTmp = std::string(CATHBOX_BINARY_DIR) + "/tests/host/cli/";

int run(const std::string& args, const std::string& err_file) {
  const int status = std::system((kBin + " " + args + " >/dev/null 2>" + err_file).c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(CathboxSimRun, LogsAreByteIdenticalAcrossRuns) {
  const std::string base = "sim run --case " + kData + "y_analytic.case --script " + kData + "y_steer.actions --every 50 --out ";
  ASSERT_EQ(run(base + kTmp + "run_a.csv", kTmp + "run_a.err"), 0) << slurp(kTmp + "run_a.err");
  ASSERT_EQ(run(base + kTmp + "run_b.csv", kTmp + "run_b.err"), 0);
  const std::string a = slurp(kTmp + "run_a.csv");
  EXPECT_EQ(a, slurp(kTmp + "run_b.csv"));
  EXPECT_EQ(std::count(a.begin(), a.end(), '\n'), 1 + 100);  // header + 5000 ms / 50 ms
}

TEST(CathboxSimRun, BadScriptIsAFileLineErrorWithExitCode2) {
  const std::string script = kTmp + "bad.actions";
  std::ofstream(script) << "0 insert_to 10\n20 turn 5\n";
  EXPECT_EQ(run("sim run --case " + kData + "y_analytic.case --script " + script + " --out " + kTmp + "bad.csv",
                kTmp + "bad.err"),
            2);
  EXPECT_EQ(slurp(kTmp + "bad.err"),
            script + ":2: unknown verb 'turn' (known: select insert_to insert_by rotate_to rotate_by end fluoro inject carm roadmap inflate deflate)\n");
}

TEST(CathboxSimRun, BadCaseAndBadArgumentsExitWith2) {
  const std::string bad_case = kTmp + "bad.case";
  std::ofstream(bad_case) << "tube 0 0 0 0 1 0 0 10 1\nentry 0 0 0 0 0 1\ntool w guidewire\n";
  EXPECT_EQ(run("sim run --case " + bad_case + " --script " + kData + "y_steer.actions --out " + kTmp + "x.csv",
                kTmp + "case.err"),
            2);
  EXPECT_EQ(slurp(kTmp + "case.err"), bad_case + ":3: tool 'w' has no 'end'\n");
  EXPECT_EQ(run("sim run --case " + bad_case, kTmp + "args.err"), 2);
  EXPECT_EQ(run("sim run --case " + kData + "y_analytic.case --script " + kData + "y_steer.actions --out " + kTmp +
                    "x.csv --every 0",
                kTmp + "every.err"),
            2);
}

}  // namespace
