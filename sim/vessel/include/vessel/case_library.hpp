#pragma once
// The case library by morphology (cases/library/): aortic arch types I-III and a bovine arch,
// cervical ICA tortuosity grades, and saccular aneurysms at the four commonest sites. Each case
// is a vessel model plus the text of its `.case` file (entry, target, tools) and of the scripted
// run (`.actions`) that reaches the target. Figures and sources: src/neuro_case.cpp, README.md.
#include <optional>
#include <string>
#include <vector>

#include "vessel/case_generator.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::vessel {

struct LibraryCase {
  std::string name;       // file stem: NAME.hclm, NAME.case, NAME.actions
  std::string title;      // the case's `name` line
  std::string about;      // comment lines of the .case (what, which tools, sources)
  NeuroMorphology morphology;
  std::string entry_segment;  // the tool enters here, along the centerline, at entry_fraction
  double entry_fraction = 0.0;
  bool entry_upstream = false;  // heading against the centerline (up the descending aorta)
  std::string target_segment;
  double target_fraction = 0.0;
  std::string tools;      // the .case's tool blocks
  std::string actions;    // the .actions script
};

// Names of the library cases, in a fixed order.
[[nodiscard]] std::vector<std::string> library_case_names();
// The named case; nullopt for an unknown name.
[[nodiscard]] std::optional<LibraryCase> library_case(const std::string& name);
// Its vessel model.
[[nodiscard]] VesselModel library_model(const LibraryCase& c);
// The .case text (vessel NAME.hclm beside it; entry and target resolved against the model).
[[nodiscard]] std::string library_case_text(const LibraryCase& c, const VesselModel& model);

}  // namespace cathbox::vessel
