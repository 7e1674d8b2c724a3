#pragma once
// The stent retriever's small Y (tests/host/session/stent_retriever_tube_test.cpp): a 3.6 mm
// parent, a 2.8 mm branch straight on (M1-sized) with a 10 mm red-cell-rich clot, a 2.4 mm side
// branch; balloon guide > microcatheter > a 4 x 20 mm stent retriever (embedding time 0.5 s), and
// the script of one pass retrieved into the guide under flow arrest. Shared with the server's
// trace test (tests/host/server/records_test.cpp).
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "session_fixtures.hpp"

namespace cathbox::session::fixtures {

// One HCLM segment: points every 2 mm from `from` along `dir` for `length_mm`.
inline std::string tube_segment(int id, const char* name, const char* links, double flow, double fx, double fz, double dx, double dz,
                    double length_mm, double radius_mm) {
  const int n = static_cast<int>(std::lround(length_mm / 2.0)) + 1;
  std::ostringstream s;
  s << "g " << id << "\nl " << name << "\nf " << flow << "\n" << links << "n " << n << "\n";
  for (int i = 0; i < n; ++i) s << "v " << fx + dx * 2.0 * i << " 0 " << fz + dz * 2.0 * i << " " << radius_mm << "\n";
  return s.str();
}

// The Y and its stack, written into CATHBOX_BINARY_DIR/`dir`; `clot` the case's clot line,
// `guide_extra` more lines for the guide. The case file's path.
inline std::string write_stent_tube_case(const char* clot = "clot 2 6 10 red=60 fibrin=30\n", const char* guide_extra = "",
                                         const std::string& dir = "session_test") {
  const double side = std::sqrt(0.5);
  const std::string hclm = "s 3\n\n" + tube_segment(1, "parent", "p 0\nc 2 2 3\n", 200, 0, 0, 0, 1, 30, 1.8) + "\n" +
                           tube_segment(2, "straight_branch", "p 1 1\nc 0\n", 120, 0, 30, 0, 1, 50, 1.4) + "\n" +
                           tube_segment(3, "side_branch", "p 1 1\nc 0\n", 80, 0, 30, side, side, 30, 1.2);
  const std::string vessel = fixtures::temp_path(dir, "stent_tube.hclm");
  std::ofstream(vessel) << hclm;
  const std::string path = fixtures::temp_path(dir, "stent_tube.case");
  std::ofstream(path) << "cathbox-case 1\n"
                         "name stent retriever in a straight branch\n"
                         "vessel " << vessel << "\n"
                      << clot << "tool guide catheter\n"
                         "  section 900 od=2.7 ei=400 gj=300\n"
                         "  section 80 od=2.7 ei=80 gj=60\n"
                         "  friction 0.15\n"
                         "  inner_diameter 2.13\n"
                         "  balloon length=10 from_tip=3 nominal=1 burst=2 chart=0.1:3,0.5:7,1:9,2:10\n"
                      << guide_extra << "end\n"
                         "tool microcatheter catheter\n"
                         "  section 1400 od=0.85 ei=8 gj=6\n"
                         "  section 150 od=0.8 ei=2 gj=1.6\n"
                         "  friction 0.1\n"
                         "  inner_diameter 0.53\n"
                         "  inside guide\n"
                         "  spacing 2 0.5 40\n"
                         "end\n"
                         "tool stent guidewire\n"
                         "  section 1700 od=0.4 ei=30 gj=23\n"
                         "  section 60 od=0.4 ei=5 gj=4\n"
                         "  section 20 od=0.45 ei=2 gj=1.5\n"
                         "  friction 0.08\n"
                         "  inside microcatheter\n"
                         "  spacing 2 0.5 30\n"
                         "  stent_retriever diameter=4 length=20 embed=0.5\n"
                         "end\n";
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
