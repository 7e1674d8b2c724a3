// cathbox-session.js: the WebAssembly session from the command line (node).
//   run --case FILE --mesh FILE.cbxmesh --script ACTIONS --record OUT.cbxrec
//   replay REC --mesh FILE.cbxmesh [--check]
// Exit codes as every Cathbox program (base/exit_codes.hpp): 0 ok, 1 a hash differs under
// --check, 2 bad input.
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "base/exit_codes.hpp"
#include "session/action_script_hand.hpp"
#include "session/metrics.hpp"
#include "session/replay.hpp"
#include "session/session.hpp"
#include "wasm/surface_file.hpp"

namespace {

using namespace cathbox;

constexpr const char* kUsage =
    "usage: cathbox-session run --case FILE --mesh FILE.cbxmesh --script ACTIONS --record OUT\n"
    "       cathbox-session replay REC --mesh FILE.cbxmesh [--check]\n";

struct Args {
  std::vector<std::string> positionals;
  std::map<std::string, std::string> values;
  bool check = false;
  std::string error;
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--check") {
      a.check = true;
    } else if (arg.starts_with("--")) {
      if (i + 1 >= argc) {
        a.error = arg + " needs a value";
        return a;
      }
      a.values[arg.substr(2)] = argv[++i];
    } else {
      a.positionals.push_back(arg);
    }
  }
  return a;
}

int bad_input(const std::string& what) {
  std::fprintf(stderr, "cathbox-session: %s\n", what.c_str());
  return base::kExitBadInput;
}

int run(const Args& a) {
  for (const char* need : {"case", "mesh", "script", "record"}) {
    if (!a.values.contains(need)) return bad_input(std::string("run needs --") + need + "\n" + kUsage);
  }
  base::Result<vessel::SurfaceMesh> surface = wasm::read_surface_file(a.values.at("mesh"));
  if (!surface) return bad_input(surface.error().message);
  session::SessionCaseLoad scene = session::load_session_case(a.values.at("case"), &*surface);
  if (!scene) return bad_input(scene.error().message);
  base::Result<std::unique_ptr<session::ActionScriptHand>> hand =
      session::ActionScriptHand::load(a.values.at("script"), *scene.value());
  if (!hand) return bad_input(hand.error().message);
  const session::SessionOptions options;
  session::Session s(std::move(scene.value()), std::move(*hand), options);
  const std::string& record = a.values.at("record");
  if (base::Status<> recording = s.record_to(record); !recording) return bad_input(recording.error().message);
  std::printf("cathbox-session (wasm): %s, %s, virtual time -> %s\n", s.scene().name.c_str(),
              s.hand_description().c_str(), record.c_str());
  while (!s.over()) s.step_virtual(1000);
  session::Recorder& rec = *s.recorder();
  const bool written = rec.close();
  std::printf("end of run (%s): %lld ticks; record %s: %llu bytes\n%s", session::record::end_reason_name(s.end_reason()),
              static_cast<long long>(s.ticks()), record.c_str(), static_cast<unsigned long long>(rec.bytes_written()),
              session::MetricsCollector::format(s.metrics()).c_str());
  if (!written) {
    std::fprintf(stderr, "%s\n", rec.error().c_str());
    return base::kExitFailure;
  }
  return base::kExitOk;
}

int replay(const Args& a) {
  if (a.positionals.size() != 1 || !a.values.contains("mesh")) return bad_input(std::string("replay needs REC and --mesh\n") + kUsage);
  base::Result<vessel::SurfaceMesh> surface = wasm::read_surface_file(a.values.at("mesh"));
  if (!surface) return bad_input(surface.error().message);
  const std::string& path = a.positionals[0];
  base::Result<std::unique_ptr<session::Replay>> replay = session::Replay::open(path, a.check, &*surface);
  if (!replay) return bad_input(replay.error().message);
  (*replay)->step(-1);
  const session::ReplayResult r = (*replay)->result();
  std::printf("%s: replayed %lld of %lld recorded ticks, %lld state hashes checked\n", path.c_str(),
              static_cast<long long>(r.ticks), static_cast<long long>(r.recorded_ticks),
              static_cast<long long>(r.hashes_checked));
  if (r.mismatch) {
    std::printf("state hash differs at tick %lld: recorded %016llx, replayed %016llx\n",
                static_cast<long long>(r.mismatch->tick), static_cast<unsigned long long>(r.mismatch->recorded),
                static_cast<unsigned long long>(r.mismatch->replayed));
  }
  if (!r.error.empty()) return bad_input(r.error);
  if (r.mismatch) return a.check ? base::kExitFailure : base::kExitOk;
  if (a.check) std::printf("every state hash matches\n");
  return base::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return bad_input(std::string("no command\n") + kUsage);
  const Args a = parse(argc, argv);
  if (!a.error.empty()) return bad_input(a.error);
  const std::string command = argv[1];
  if (command == "run") return run(a);
  if (command == "replay") return replay(a);
  return bad_input("unknown command '" + command + "'\n" + kUsage);
}
