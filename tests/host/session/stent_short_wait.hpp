#pragma once
// The bundled M1 stent-retriever case and script with the embedding time cut from 180 s to 5 s:
// the case's `embed=` and every script time from the end of the wait on moved 175 s earlier.
// The bundled wait costs ~150 s of CPU (the whole script 196 s); the access, unsheathing and
// retrieval are the same. Run by stent_retriever_session_test.cpp and, as the stent run of
// hand_force_jumps_test.cpp, with every tick over the box's slew printed.
#include <gtest/gtest.h>

#include <cctype>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>

#include "base/read_file.hpp"
#include "session_fixtures.hpp"

namespace cathbox::session::fixtures {

constexpr std::int64_t kStentWaitCut_ms = 175'000;

// The short-wait case, written below the build tree as `file` (each test its own: ctest runs
// them side by side, and one writing the file another reads would hand it a part); its path.
inline std::string stent_short_wait_case(const std::string& file) {
  std::string text = base::read_file(case_path("neuro_thrombectomy_m1_stentretriever.case"), 1 << 20).value();
  const auto replace = [&](const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  };
  replace("embed=180", "embed=5");
  replace("\nvessel neuro.hclm", "\nvessel " + case_path("neuro.hclm"));
  const std::string path = temp_path("session_test", file);
  std::ofstream(path) << text;
  return path;
}

// A bundled script's text (cases/<name>) with every time after 48 s moved the cut earlier.
inline std::string stent_short_wait_script(const std::string& name = "neuro_thrombectomy_m1_stentretriever.actions") {
  std::ifstream in(case_path(name));
  std::ostringstream out;
  std::string line;
  while (std::getline(in, line)) {
    std::int64_t at_ms = 0;
    std::size_t digits = 0;
    if (!line.empty() && std::isdigit(static_cast<unsigned char>(line[0])) != 0) at_ms = std::stoll(line, &digits);
    if (at_ms > 48'000) line = std::to_string(at_ms - kStentWaitCut_ms) + line.substr(digits);
    out << line << '\n';
  }
  return out.str();
}

}  // namespace cathbox::session::fixtures
