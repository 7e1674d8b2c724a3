#pragma once
// The command line of cathbox-trainer. Parsing never exits or throws: errors come back as one
// line naming the option.
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace cathbox::app {

enum class BoxChoice {
  kAuto,      // a real box if one is found, else start the emulator
  kEmulator,  // always the emulator (optionally at a given socket path)
  kNone,      // no box: keyboard and mouse, or the scripted hand
};

struct TrainerOptions {
  std::string case_path;          // empty: the default case from cases_dir
  std::string cases_dir;          // empty: <source>/cases, or ./cases
  BoxChoice box = BoxChoice::kAuto;
  std::string emu_socket;         // --emu PATH
  bool headless = false;          // no visible window (with --frames: hidden window, e.g. Xvfb)
  int frames = 0;                 // headless: render this many frames, then stop
  int sim_ms_per_frame = 16;      // headless frames: simulated time per frame (virtual time)
  std::string screenshot;         // PNG of the last frame
  int width = 1280;
  int height = 720;
  double bench_seconds = 0.0;     // > 0: benchmark run (real time), prints frame and haptic rates
  int fps_cap = 60;               // frame pacing without vsync (Xvfb, bench): 0 = as fast as possible
  double max_seconds = 0.0;       // stop after this long (headless run: simulated time); 0: no limit
  bool wireframe = false;
  std::string replay;             // --replay FILE: open in Replay mode on this record
  std::string records_dir;        // where runs are recorded (empty: session::records_dir())
  bool record = true;             // --no-record: do not record live runs
  // cathbox-server (host/app/server_link.hpp); also from the settings file.
  std::string server_url;         // --server URL: empty = no server
  std::string server_user;        // --user NAME
  std::string password_file;      // --password-file FILE (else $CATHBOX_PASSWORD)
  std::string rig;                // --rig NAME (default: the host name)
  std::optional<std::int64_t> assignment;  // --assignment ID: run this assignment's case
  std::string settings_file;      // --settings FILE (default: trainer_settings_path())
  bool help = false;
};

struct OptionsResult {
  std::optional<TrainerOptions> options;
  std::string error;
};

[[nodiscard]] OptionsResult parse_trainer_options(std::span<const char* const> args);
[[nodiscard]] const char* trainer_usage();

}  // namespace cathbox::app
