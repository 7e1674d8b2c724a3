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
            script + ":2: unknown verb 'turn' (known: select insert_to insert_by rotate_to rotate_by end fluoro inject carm roadmap detach load_coil inflate deflate aspiration balloon_guide)\n");
}

// A coil tool and a declared sac: a detach too early is a file:line note and the run goes on;
// the figures close the output (sphere cap of R 3.2, h 6.24: 137.0 mm3; pi/4 0.25^2 20 / 137 = 0.7 %).
TEST(CathboxSimRun, CoilingPrintsItsFiguresAndRefusedDetaches) {
  const std::string c = kTmp + "coil.case";
  std::ofstream(c) << "tube 0 0 0 -5 1 0 0 20 1\ntube 1 0 0 20 3.2 0 0 20.001 3.2\nentry 0 0 -3 0 0 1\n"
                      "aneurysm 0 0 20 3.2 0 0 16.96\n"
                      "tool microcatheter catheter\n section 300 od=0.7 ei=2 gj=1.6\n inner_diameter 0.45\n spacing 1 0.5\nend\n"
                      "tool coil coil\n section 300 od=0.33 ei=10 gj=8\n section 20 od=0.25 ei=0.02 gj=0.016 shape=helix loop=4\n"
                      " detach 20\n inside microcatheter\n spacing 1 0.5 22\nend\n";
  const std::string script = kTmp + "coil.actions";
  std::ofstream(script) << "0 select microcatheter\n0 insert_to 21 at 40\n600 select coil\n600 insert_to 20.5 at 40\n"
                           "1200 insert_to 31 at 20\n1800 detach\n1800 insert_to 42 at 20\n2500 detach\n2600 end\n";
  const std::string out = kTmp + "coil.out";
  const int status = std::system((kBin + " sim run --case " + c + " --script " + script + " --out " + kTmp +
                                  "coil.csv >" + out + " 2>" + kTmp + "coil.err").c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << slurp(kTmp + "coil.err");
  EXPECT_EQ(slurp(kTmp + "coil.err"), script + ":6: detach: the coil's detachment zone is still inside the catheter\n");
  EXPECT_NE(slurp(out).find("coil: 20.0 mm deployed, packing density 0.7 % of a 137.0 mm3 sac, 0 herniations"),
            std::string::npos)
      << slurp(out);
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
