#include "app/trainer_options.hpp"

#include <charconv>
#include <cstdio>
#include <string_view>

namespace cathbox::app {
namespace {

// The argument as it may appear in a one-line message: control bytes as \xNN, cut at 60.
std::string printable(std::string_view text) {
  std::string out;
  for (const char c : text.substr(0, 60)) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7F) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", u);
      out += buf;
    } else {
      out += c;
    }
  }
  if (text.size() > 60) out += "...";
  return out;
}

template <class T>
bool parse_number(std::string_view text, T& out) {
  const auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc() && p == text.data() + text.size();
}

}  // namespace

const char* trainer_usage() {
  return "usage: cathbox-trainer [options]\n"
         "  --case FILE          case to open (default: the default case in the cases folder)\n"
         "  --cases DIR          cases folder for the picker (default: the project's cases/)\n"
         "  --emu [PATH]         use the emulated box (cathbox-emu), at PATH if given\n"
         "  --no-box             no box: keyboard and mouse (or the scripted hand when headless)\n"
         "  --headless           no visible window; without --frames, run the case with the\n"
         "                       scripted hand in virtual time and print the end-of-run summary\n"
         "  --frames N           headless: render N frames in a hidden window (needs X, e.g. Xvfb)\n"
         "  --ms-per-frame MS    headless frames: simulated milliseconds per frame (default 16)\n"
         "  --screenshot OUT.png write the last frame as PNG (and OUT.png.txt with the camera)\n"
         "  --size WxH           window size (default 1280x720)\n"
         "  --bench SECONDS      measure frame time and haptic rate for SECONDS, print them, exit\n"
         "  --fps N              without vsync (Xvfb, --bench), pace frames at N per second\n"
         "                       (default 60, as a display would; 0: as fast as possible)\n"
         "  --seconds S          stop after S seconds (headless: simulated seconds)\n"
         "  --wireframe          start with the vessel in wireframe\n"
         "  --replay FILE        open a record (*.cbxrec) in Replay mode: play, pause, seek, speed\n"
         "  --records DIR        record every run into DIR (default:\n"
         "                       $XDG_DATA_HOME/cathbox/records, else ~/.local/share/cathbox/records)\n"
         "  --no-record          do not record runs\n"
         "  --server URL         join a cathbox-server (http://HOST:PORT): log in, run the assigned\n"
         "                       cases, stream the run live, upload its record (queued on disk\n"
         "                       while the server is unreachable)\n"
         "  --user NAME          the trainee's account on the server\n"
         "  --password-file FILE the password (first line); default: $CATHBOX_PASSWORD\n"
         "  --rig NAME           the rig's name instructors see (default: the host name)\n"
         "  --assignment ID      run this assignment's case (default: the first assigned)\n"
         "  --settings FILE      settings (JSON: server, user, password_file, rig); default:\n"
         "                       $XDG_CONFIG_HOME/cathbox/trainer.json, else ~/.config/...\n"
         "  --help               this text\n";
}

OptionsResult parse_trainer_options(std::span<const char* const> args) {
  TrainerOptions o;
  OptionsResult r;
  auto fail = [&](const std::string& msg) {
    r.error = msg;
    return r;
  };
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string_view a = args[i];
    auto value = [&](std::string_view& out) {
      if (i + 1 >= args.size()) return false;
      out = args[++i];
      return true;
    };
    std::string_view v;
    if (a == "--help" || a == "-h") {
      o.help = true;
    } else if (a == "--case") {
      if (!value(v)) return fail("--case needs a file");
      o.case_path = v;
    } else if (a == "--cases") {
      if (!value(v)) return fail("--cases needs a folder");
      o.cases_dir = v;
    } else if (a == "--emu") {
      o.box = BoxChoice::kEmulator;
      if (i + 1 < args.size() && std::string_view(args[i + 1]).substr(0, 2) != "--") o.emu_socket = args[++i];
    } else if (a == "--no-box") {
      o.box = BoxChoice::kNone;
    } else if (a == "--headless") {
      o.headless = true;
    } else if (a == "--frames") {
      if (!value(v) || !parse_number(v, o.frames) || o.frames < 1 || o.frames > 1'000'000)
        return fail("--frames needs a count from 1 to 1000000");
    } else if (a == "--ms-per-frame") {
      if (!value(v) || !parse_number(v, o.sim_ms_per_frame) || o.sim_ms_per_frame < 0 ||
          o.sim_ms_per_frame > 10'000)
        return fail("--ms-per-frame needs milliseconds from 0 to 10000");
    } else if (a == "--screenshot") {
      if (!value(v) || v.empty()) return fail("--screenshot needs a file name");
      o.screenshot = v;
    } else if (a == "--size") {
      const std::size_t x = value(v) ? v.find('x') : std::string_view::npos;
      if (x == std::string_view::npos || !parse_number(v.substr(0, x), o.width) ||
          !parse_number(v.substr(x + 1), o.height) || o.width < 64 || o.height < 64 ||
          o.width > 8192 || o.height > 8192)
        return fail("--size needs WxH, each from 64 to 8192");
    } else if (a == "--bench") {
      if (!value(v) || !parse_number(v, o.bench_seconds) || !(o.bench_seconds > 0.0) ||
          o.bench_seconds > 3600.0)
        return fail("--bench needs seconds (0 < s <= 3600)");
    } else if (a == "--fps") {
      if (!value(v) || !parse_number(v, o.fps_cap) || o.fps_cap < 0 || o.fps_cap > 1000)
        return fail("--fps needs frames per second from 0 to 1000");
    } else if (a == "--seconds") {
      if (!value(v) || !parse_number(v, o.max_seconds) || !(o.max_seconds > 0.0) ||
          o.max_seconds > 86400.0)
        return fail("--seconds needs simulated seconds (0 < s <= 86400)");
    } else if (a == "--wireframe") {
      o.wireframe = true;
    } else if (a == "--replay") {
      if (!value(v) || v.empty()) return fail("--replay needs a record file");
      o.replay = v;
    } else if (a == "--records") {
      if (!value(v) || v.empty()) return fail("--records needs a folder");
      o.records_dir = v;
    } else if (a == "--no-record") {
      o.record = false;
    } else if (a == "--server") {
      if (!value(v) || !v.starts_with("http://")) return fail("--server needs a URL http://HOST:PORT");
      o.server_url = v;
    } else if (a == "--user") {
      if (!value(v) || v.empty()) return fail("--user needs a name");
      o.server_user = v;
    } else if (a == "--password-file") {
      if (!value(v) || v.empty()) return fail("--password-file needs a file");
      o.password_file = v;
    } else if (a == "--rig") {
      if (!value(v) || v.empty()) return fail("--rig needs a name");
      o.rig = v;
    } else if (a == "--assignment") {
      std::int64_t id = 0;
      if (!value(v) || !parse_number(v, id) || id < 1) return fail("--assignment needs an assignment id (1 or more)");
      o.assignment = id;
    } else if (a == "--settings") {
      if (!value(v) || v.empty()) return fail("--settings needs a file");
      o.settings_file = v;
    } else {
      return fail("unknown option '" + printable(a) + "' (see --help)");
    }
  }
  if (!o.screenshot.empty() && o.frames == 0) return fail("--screenshot needs --frames N");
  if (o.frames > 0 && !o.headless) return fail("--frames needs --headless");
  if (o.bench_seconds > 0.0 && o.frames > 0) return fail("--bench and --frames exclude each other");
  if (!o.replay.empty() && (o.bench_seconds > 0.0 || !o.case_path.empty())) {
    return fail("--replay excludes --bench and --case (the record holds its case)");
  }
  r.options = o;
  return r;
}

}  // namespace cathbox::app
