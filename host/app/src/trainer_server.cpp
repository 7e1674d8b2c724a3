// cathbox-trainer and cathbox-server: the link opened from the options and the settings file,
// the assigned cases offered first, and each closed run handed to the upload queue.
#include <algorithm>
#include <cstdio>

#include "app/server_link.hpp"
#include "app/trainer_app.hpp"
#include "app/trainer_settings.hpp"
#include "base/exit_codes.hpp"

namespace cathbox::app {

void TrainerApp::close_live(bool background_upload) {
  if (!live_) return;
  live_.reset();
  if (link_) {
    const std::string problem = link_->end_run(options_.record ? record_path_ : std::string(), live_assignment_, background_upload);
    if (!problem.empty()) std::fprintf(stderr, "cathbox-trainer: %s (the record stays in %s)\n", problem.c_str(), record_path_.c_str());
  }
  live_assignment_.reset();
}

int TrainerApp::open_server_link() {
  if (base::Status<> applied = apply_trainer_settings(options_); !applied) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", applied.error().message.c_str());
    return base::kExitBadInput;
  }
  if (options_.server_url.empty()) {
    if (options_.assignment) {
      std::fprintf(stderr, "cathbox-trainer: --assignment needs --server (or \"server\" in the settings file)\n");
      return base::kExitBadInput;
    }
    return -1;
  }
  base::Result<ServerLinkOptions> link_options = server_link_options(options_);
  if (!link_options) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", link_options.error().message.c_str());
    return base::kExitBadInput;
  }
  std::string note;
  link_ = ServerLink::open(*link_options, note);
  if (!note.empty()) std::fprintf(stderr, "cathbox-trainer: %s\n", note.c_str());
  std::printf("cathbox-trainer: %s\n", link_->status_line().c_str());
  for (const AssignedCase& a : link_->assigned()) {
    std::printf("  assignment %lld: %s%s%s\n", static_cast<long long>(a.info.id), a.info.case_name.c_str(),
                a.info.due_at.empty() ? "" : (", due " + a.info.due_at).c_str(), a.info.note.empty() ? "" : (" - " + a.info.note).c_str());
  }
  std::fflush(stdout);
  if (options_.assignment) {
    const auto& list = link_->assigned();
    const bool known = std::any_of(list.begin(), list.end(), [&](const AssignedCase& a) { return a.info.id == *options_.assignment; });
    if (!known) {
      std::fprintf(stderr, "cathbox-trainer: --assignment %lld: not among this trainee's assignments%s\n",
                   static_cast<long long>(*options_.assignment), link_->online() ? "" : " (offline: none cached)");
      return base::kExitBadInput;
    }
  }
  return -1;
}

CaseChoice TrainerApp::choose() {
  std::vector<CaseEntry> assigned;
  std::string assigned_path;
  if (link_) {
    for (const AssignedCase& a : link_->assigned()) {
      assigned.push_back({"assigned " + std::to_string(a.info.id) + ": " + a.info.case_name, a.case_path});
      if (assigned_path.empty() && (!options_.assignment || *options_.assignment == a.info.id)) assigned_path = a.case_path;
    }
  }
  TrainerOptions o = options_;
  if (o.case_path.empty()) o.case_path = assigned_path;
  CaseChoice c = choose_case(o, program_dir_, catalog_);
  if (!assigned.empty()) {
    catalog_.prepend(std::move(assigned));
    c.catalog_index = catalog_.index_of_path(c.path) >= 0 ? catalog_.index_of_path(c.path) : c.catalog_index;
  }
  return c;
}

}  // namespace cathbox::app
