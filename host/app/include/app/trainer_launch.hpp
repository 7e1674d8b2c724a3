#pragma once
// How the trainer starts a run: which case (the one asked for, else the default of the cases
// folder), which hand (the scripted hand without anyone at the keyboard; else the box, real or
// emulated, with the keyboard on top; else the keyboard alone), and the record of the run
// (every live run, into the records folder). All through host/session.
#include <memory>
#include <string>

#include "app/case_catalog.hpp"
#include "app/trainer_options.hpp"
#include "session/keyboard_input.hpp"
#include "session/session.hpp"

namespace cathbox::app {

struct CaseChoice {
  std::string path;      // empty when there is none (error says why)
  int catalog_index = -1;
  std::string error;
};

// The case to open, and the catalog of the cases folder for the picker.
[[nodiscard]] CaseChoice choose_case(const TrainerOptions& options, const std::string& program_dir, CaseCatalog& catalog);

struct LiveSession {
  std::unique_ptr<session::Session> session;
  std::string record_path;  // empty when not recording
  std::string error;        // one line when session is null
  std::string note;         // e.g. why there is no box or no record
};

// Loads the case and connects the hand; `scripted`: the autopilot drives (headless, bench).
[[nodiscard]] LiveSession open_live_session(const TrainerOptions& options, const std::string& program_dir,
                                            const std::string& case_path, bool scripted,
                                            session::KeyboardInput& keyboard);

}  // namespace cathbox::app
