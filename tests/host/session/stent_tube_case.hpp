#pragma once
// The stent retriever's small Y (tests/host/session/stent_retriever_tube_test.cpp): a 3.6 mm
// parent, a 2.8 mm branch straight on (M1-sized) with a 10 mm red-cell-rich clot, a 2.4 mm side
// branch; balloon guide > microcatheter > a 4 x 20 mm stent retriever (embedding time 0.5 s), and
// the script of one pass retrieved into the guide under flow arrest. Shared with the server's
// trace test (tests/host/server/records_test.cpp).
#include <fstream>
#include <sstream>
#include <string>
#include <utility>

#include "session_fixtures.hpp"

namespace cathbox::session::fixtures {

// The bundled text of tests/host/session/data/stent_tube.`ext` (also read by the trainee page's
// browser test, tests/browser/train_stent.py).
inline std::string stent_tube_data(const char* ext) {
  std::ifstream in(std::string(CATHBOX_SOURCE_DIR) + "/tests/host/session/data/stent_tube." + ext);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The Y and its stack, written into CATHBOX_BINARY_DIR/`dir`; `clot` replaces the case's clot
// line, `guide_extra` are more lines for the guide (before its `end`). The case file's path.
inline std::string write_stent_tube_case(const char* clot = "clot 2 6 10 red=60 fibrin=30\n", const char* guide_extra = "",
                                         const std::string& dir = "session_test") {
  const std::string vessel = fixtures::temp_path(dir, "stent_tube.hclm");
  std::ofstream(vessel) << stent_tube_data("hclm");
  std::string text = stent_tube_data("case");
  const auto line = [&](const std::string& head) {
    const std::size_t at = text.find("\n" + head) + 1;
    return std::pair{at, text.find('\n', at) + 1 - at};
  };
  const auto [clot_at, clot_n] = line("clot ");
  text.replace(clot_at, clot_n, clot);
  text.insert(line("end").first, guide_extra);  // the guide is the first tool
  const auto [vessel_at, vessel_n] = line("vessel ");
  text.replace(vessel_at, vessel_n, "vessel " + vessel + "\n");
  const std::string path = fixtures::temp_path(dir, "stent_tube.case");
  std::ofstream(path) << text;
  return path;
}

// Guide to 20 mm, the microcatheter across the clot (36-46 mm from the entry) to 56 mm, the
// stent to 6 mm short of its tip, unsheathed by drawing the microcatheter back 30 mm; flow
// arrest, the dwell, the microcatheter into the guide, the stent pulled into the guide.
inline constexpr const char* kStentTubeScript =
    "0 select guide\n0 insert_to 20 at 40\n"
    "0 select microcatheter\n0 insert_to 56 at 40\n"
    "1500 select stent\n1500 insert_to 50 at 50\n"
    "2500 select microcatheter\n2500 insert_by -30 at 20\n"
    "4000 select guide\n4000 balloon_guide inflate\n"
    "4600 select microcatheter\n4600 insert_to 15 at 40\n"
    "4900 select stent\n4900 insert_to 10 at 20\n"
    "6900 select guide\n6900 balloon_guide deflate\n"
    "7000 end\n";

}  // namespace cathbox::session::fixtures
