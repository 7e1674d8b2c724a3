#pragma once
// The trainer's settings file: what a rig keeps between runs so the trainee types nothing but
// `cathbox-trainer`. JSON, every field optional, the command line wins:
//   {"server": "http://centre.example:8080", "user": "ann", "password_file": "/etc/cathbox/ann",
//    "rig": "rig-07"}
// A missing file is no error; a damaged one is refused with one line naming the file and field.
#include <string>

#include "app/server_link.hpp"
#include "app/trainer_options.hpp"
#include "base/result.hpp"

namespace cathbox::app {

// $XDG_CONFIG_HOME/cathbox/trainer.json, else ~/.config/cathbox/trainer.json.
[[nodiscard]] std::string trainer_settings_path();

// Fills the server options the command line left empty from options.settings_file (or the
// default path); or one line naming a damaged file.
[[nodiscard]] base::Status<> apply_trainer_settings(TrainerOptions& options);

// The link's options from the trainer's: the password from password_file (its first line) or
// $CATHBOX_PASSWORD; or one line when the user or the password is missing.
[[nodiscard]] base::Result<ServerLinkOptions> server_link_options(const TrainerOptions& options);

}  // namespace cathbox::app
