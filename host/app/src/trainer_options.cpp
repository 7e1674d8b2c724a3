#include "app/trainer_options.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <functional>
#include <string_view>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "base/text_tokens.hpp"

namespace cathbox::app {
namespace {

// The argument as it may appear in a one-line message: control bytes as \xNN, cut at 60.
std::string printable(std::string_view text) { return base::text::escape_bytes(text, 60); }

template <class T>
bool parse_number(std::string_view text, T& out) {
  const auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc() && p == text.data() + text.size();
}

// One option with a value: its help line, and how its value is checked and kept (false: the
// option's one-line error). A value left out comes as "".
struct ValueOption {
  const char* name;
  const char* value_name;
  const char* help;
  const char* error;
  std::function<bool(std::string_view, TrainerOptions&)> apply;
};

bool text(std::string_view v, std::string& out) {
  out = v;
  return !v.empty();
}

// Stays whole: a table, one entry per option (flag, argument, help, refusal, parser), read top to
// bottom like --help; splitting it would only scatter the options.
std::vector<ValueOption> value_options() {  // NOLINT(readability-function-size)
  return {
      {"--case", "FILE", "case to open (default: the default case in the cases folder)", "--case needs a file",
       [](std::string_view v, TrainerOptions& o) { return text(v, o.case_path); }},
      {"--cases", "DIR",
       "cases folder for the picker (default: ../share/cathbox/cases beside the program, else the project's cases/)",
       "--cases needs a folder",
       [](std::string_view v, TrainerOptions& o) { return text(v, o.cases_dir); }},
      {"--frames", "N", "headless: render N frames in a hidden window (needs X, e.g. Xvfb)",
       "--frames needs a count from 1 to 1000000",
       [](std::string_view v, TrainerOptions& o) { return parse_number(v, o.frames) && o.frames >= 1 && o.frames <= 1'000'000; }},
      {"--ms-per-frame", "MS", "headless frames: simulated milliseconds per frame (default 16)",
       "--ms-per-frame needs milliseconds from 0 to 10000",
       [](std::string_view v, TrainerOptions& o) {
         return parse_number(v, o.sim_ms_per_frame) && o.sim_ms_per_frame >= 0 && o.sim_ms_per_frame <= 10'000;
       }},
      {"--screenshot", "OUT.png", "write the last frame as PNG (and OUT.png.txt with the camera)",
       "--screenshot needs a file name", [](std::string_view v, TrainerOptions& o) { return text(v, o.screenshot); }},
      {"--size", "WxH", "window size (default 1280x720)", "--size needs WxH, each from 64 to 8192",
       [](std::string_view v, TrainerOptions& o) {
         const std::size_t x = v.find('x');
         return x != std::string_view::npos && parse_number(v.substr(0, x), o.width) &&
                parse_number(v.substr(x + 1), o.height) && o.width >= 64 && o.height >= 64 && o.width <= 8192 &&
                o.height <= 8192;
       }},
      {"--bench", "SECONDS", "measure frame time and haptic rate for SECONDS, print them, exit",
       "--bench needs seconds (0 < s <= 3600)",
       [](std::string_view v, TrainerOptions& o) {
         return parse_number(v, o.bench_seconds) && o.bench_seconds > 0.0 && o.bench_seconds <= 3600.0;
       }},
      {"--fps", "N",
       "without vsync (Xvfb, --bench), pace frames at N per second (default 60, as a display would; 0: as fast as "
       "possible)",
       "--fps needs frames per second from 0 to 1000",
       [](std::string_view v, TrainerOptions& o) { return parse_number(v, o.fps_cap) && o.fps_cap >= 0 && o.fps_cap <= 1000; }},
      {"--seconds", "S", "stop after S seconds (headless: simulated seconds)",
       "--seconds needs simulated seconds (0 < s <= 86400)",
       [](std::string_view v, TrainerOptions& o) {
         return parse_number(v, o.max_seconds) && o.max_seconds > 0.0 && o.max_seconds <= 86400.0;
       }},
      {"--speed", "X",
       "headless run: X simulated seconds per second of wall time, as a rig streams (default 0: as fast as "
       "possible)",
       "--speed needs a factor (0 <= x <= 1000)",
       [](std::string_view v, TrainerOptions& o) { return parse_number(v, o.speed) && o.speed >= 0.0 && o.speed <= 1000.0; }},
      {"--box", "TOOL=WHERE",
       "a box per tool, repeated (two or more): WHERE is a real box's serial, emu (start one) or emu:PATH; each "
       "box drives and renders only its tool",
       "--box needs TOOL=WHERE",
       [](std::string_view v, TrainerOptions& o) {
         const std::size_t eq = v.find('=');
         if (eq == std::string_view::npos || eq == 0 || eq + 1 == v.size()) return false;
         o.boxes.emplace_back(v);
         return true;
       }},
      {"--view", "fluoro|3d",
       "the main view: fluoro (the fluoroscopic image) or 3d (the vessel tree); default: fluoro for a `realistic` case, "
       "else 3d",
       "--view needs fluoro or 3d",
       [](std::string_view v, TrainerOptions& o) {
         if (v != "fluoro" && v != "3d") return false;
         o.view = v == "fluoro" ? MainView::kFluoro : MainView::k3d;
         return true;
       }},
      {"--replay", "FILE", "open a record (*.cbxrec) in Replay mode: play, pause, seek, speed",
       "--replay needs a record file", [](std::string_view v, TrainerOptions& o) { return text(v, o.replay); }},
      {"--records", "DIR",
       "record every run into DIR (default: $XDG_DATA_HOME/cathbox/records, else ~/.local/share/cathbox/records)",
       "--records needs a folder", [](std::string_view v, TrainerOptions& o) { return text(v, o.records_dir); }},
      {"--server", "URL",
       "join a cathbox-server (https://HOST:PORT, or http:// on loopback): log in, run the assigned cases, stream the run "
       "live, upload its record (queued on disk while the server is unreachable)",
       "--server needs a URL https://HOST:PORT or http://HOST:PORT",
       [](std::string_view v, TrainerOptions& o) {
         return (v.starts_with("http://") || v.starts_with("https://")) && text(v, o.server_url);
       }},
      {"--ca-file", "FILE", "trust the server's certificate from this PEM CA file (default: the system trust store)",
       "--ca-file needs a PEM file", [](std::string_view v, TrainerOptions& o) { return text(v, o.ca_file); }},
      {"--user", "NAME", "the trainee's account on the server", "--user needs a name",
       [](std::string_view v, TrainerOptions& o) { return text(v, o.server_user); }},
      {"--password-file", "FILE", "the password (first line); default: $CATHBOX_PASSWORD",
       "--password-file needs a file", [](std::string_view v, TrainerOptions& o) { return text(v, o.password_file); }},
      {"--rig", "NAME", "the rig's name instructors see (default: the host name)", "--rig needs a name",
       [](std::string_view v, TrainerOptions& o) { return text(v, o.rig); }},
      {"--assignment", "ID", "run this assignment's case (default: the first assigned)",
       "--assignment needs an assignment id (1 or more)",
       [](std::string_view v, TrainerOptions& o) {
         std::int64_t id = 0;
         if (!parse_number(v, id) || id < 1) return false;
         o.assignment = id;
         return true;
       }},
      {"--settings", "FILE",
       "settings (JSON: server, user, password_file, rig); default: $XDG_CONFIG_HOME/cathbox/trainer.json, else "
       "~/.config/cathbox/trainer.json",
       "--settings needs a file", [](std::string_view v, TrainerOptions& o) { return text(v, o.settings_file); }},
      {"--script", "ACTIONS",
       "an action script (*.actions) drives the run instead of the hand: tools, pedal, injections, C-arm, roadmap "
       "(with --headless, in virtual time)",
       "--script needs an action script file", [](std::string_view v, TrainerOptions& o) { return text(v, o.script); }},
      {"--pedal-gpio", "CHIP:LINE",
       "the fluoroscopy foot pedal on a GPIO line, e.g. gpiochip0:22 (add :active-high for a switch to 3.3 V; "
       "default active-low with the pull-up); the Space key works too",
       "--pedal-gpio needs CHIP:LINE", [](std::string_view v, TrainerOptions& o) { return text(v, o.pedal_gpio); }},
  };
}

// The options as CLI11 knows them: the value options, the flags and --emu [PATH]; the values
// are checked after parsing, in the order the options were given.
struct Parser {
  CLI::App app{"cathbox-trainer: the trainee's application (host/app/README.md)", "cathbox-trainer"};
  std::vector<ValueOption> values = value_options();
  std::vector<CLI::Option*> value_ptrs;
  CLI::Option* emu = nullptr;
  CLI::Option* no_box = nullptr;
  CLI::Option* headless = nullptr;
  CLI::Option* wireframe = nullptr;
  CLI::Option* picker = nullptr;
  CLI::Option* no_record = nullptr;

  Parser() {
    app.set_help_flag("-h,--help", "this text");
    app.allow_extras();
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    app.get_formatter()->column_width(26);
    auto flag = [&](const char* name, const char* help) {
      return app.add_flag(name)->description(help)->disable_flag_override();
    };
    // In the order --help lists them.
    for (const ValueOption& v : values) {
      const std::string_view name = v.name;
      if (name == "--frames") {
        emu = app.add_option("--emu")->expected(0, 1)->type_name("[PATH]")->description(
            "use the emulated box (cathbox-emu), at PATH if given");
        no_box = flag("--no-box", "no box: keyboard and mouse (or the scripted hand when headless)");
        headless = flag("--headless",
                        "no visible window; without --frames, run the case with the scripted hand in virtual time "
                        "(with --emu or --box: through the box, in real time) and print the end-of-run summary");
      } else if (name == "--replay") {
        wireframe = flag("--wireframe", "start with the vessel in wireframe");
        picker = flag("--picker", "start with the case picker open (each case's anatomy thumbnail and description)");
      } else if (name == "--server") {
        no_record = flag("--no-record", "do not record runs");
      }
      value_ptrs.push_back(app.add_option(v.name)->expected(0, 1)->type_name(v.value_name)->description(v.help));
    }
  }
};

}  // namespace

std::string trainer_usage() { return Parser().app.help(); }

OptionsResult parse_trainer_options(std::span<const char* const> args) {
  TrainerOptions o;
  OptionsResult r;
  auto fail = [&](const std::string& msg) {
    r.error = msg;
    return r;
  };
  Parser p;
  std::vector<std::string> reversed;
  for (auto it = args.rbegin(); it != args.rend(); ++it) reversed.emplace_back(*it);
  try {
    p.app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    o.help = true;
    r.options = o;
    return r;
  } catch (const CLI::Error&) {
    // The one error CLI11 raises here: a value given to a flag (`--headless=1`).
    const auto given = std::find_if(args.begin(), args.end(), [](const char* a) {
      return std::string_view(a).starts_with("--") && std::string_view(a).find('=') != std::string_view::npos;
    });
    return fail("unknown option '" + printable(given == args.end() ? "" : *given) + "' (see --help)");
  }
  if (const std::vector<std::string> extra = p.app.remaining(); !extra.empty()) {
    return fail("unknown option '" + printable(extra.front()) + "' (see --help)");
  }
  for (std::size_t i = 0; i < p.values.size(); ++i) {
    if (p.value_ptrs[i]->count() == 0) continue;
    if (std::string_view(p.values[i].name) == "--box") {
      // Every --box, in the order given.
      for (const std::string& v : p.value_ptrs[i]->results()) {
        if (!p.values[i].apply(v, o)) return fail(p.values[i].error);
      }
    } else if (!p.values[i].apply(p.value_ptrs[i]->as<std::string>(), o)) {
      return fail(p.values[i].error);
    }
  }
  if (p.emu->count() > 0) {
    o.box = BoxChoice::kEmulator;
    o.emu_socket = p.emu->as<std::string>();
  }
  if (p.no_box->count() > 0) o.box = BoxChoice::kNone;
  o.headless = p.headless->count() > 0;
  o.wireframe = p.wireframe->count() > 0;
  o.picker = p.picker->count() > 0;
  o.record = p.no_record->count() == 0;
  if (o.boxes.size() == 1) return fail("--box needs two boxes or more (one box: --emu, which switches between tools)");
  if (!o.boxes.empty() && (p.emu->count() > 0 || o.box == BoxChoice::kNone)) return fail("--box excludes --emu and --no-box");
  if (!o.screenshot.empty() && o.frames == 0) return fail("--screenshot needs --frames N");
  if (o.frames > 0 && !o.headless) return fail("--frames needs --headless");
  if (o.speed > 0.0 && (!o.headless || o.frames > 0)) return fail("--speed needs --headless (without --frames)");
  if (o.bench_seconds > 0.0 && o.frames > 0) return fail("--bench and --frames exclude each other");
  if (!o.replay.empty() && (o.bench_seconds > 0.0 || !o.case_path.empty())) {
    return fail("--replay excludes --bench and --case (the record holds its case)");
  }
  r.options = o;
  return r;
}

}  // namespace cathbox::app
