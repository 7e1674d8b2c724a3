#include "session_run.hpp"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "cli/args.hpp"
#include "cli/exit_codes.hpp"
#include "session/action_script_hand.hpp"
#include "session/box_hand.hpp"
#include "session/multi_box_hand.hpp"
#include "session/session.hpp"
#include "session/tool_forces.hpp"

namespace cathbox::cli {
namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void on_signal(int) { g_interrupted.store(true); }

void print_events(session::Session& s) {
  session::LogEvent e;
  while (s.events().pop(e)) std::printf("%8.3f s  %s\n", static_cast<double>(e.time_us) * 1e-6, e.text.data());
}

std::string program_dir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : exe.parent_path().string();
}

// The hand that drives a run; without one, the exit code (its message printed) or, for a bad
// --box, the usage problem.
struct HandChoice {
  std::unique_ptr<session::Hand> hand;
  int exit_code = kExitOk;
  std::string usage_problem;
};

HandChoice script_hand(const std::string& script, const session::SessionCase& scene) {
  base::Result<std::unique_ptr<session::ActionScriptHand>> loaded = session::ActionScriptHand::load(script, scene);
  if (!loaded) {
    std::fprintf(stderr, "%s\n", loaded.error().message.c_str());
    return {nullptr, kExitBadInput, {}};
  }
  return {std::move(*loaded), kExitOk, {}};
}

// --emu [PATH]: the emulated box at PATH, or one started for this run.
HandChoice emulator_hand(const std::string& emu, const session::SessionOptions& options) {
  session::BoxHandOptions box;
  box.source = session::BoxSource::kEmulator;
  box.emu_socket = emu;
  box.emu_program = program_dir() + "/cathbox-emu";
  box.dt_s = static_cast<double>(options.period_us) * 1e-6;
  base::Result<std::unique_ptr<session::BoxHand>> connected = session::BoxHand::connect(box);
  if (!connected) {
    std::fprintf(stderr, "cathbox session run: %s\n", connected.error().message.c_str());
    return {nullptr, kExitNoDevice, {}};
  }
  return {std::move(*connected), kExitOk, {}};
}

// --box TOOL=WHERE, repeated: one box per tool, each tool once.
HandChoice box_rig_hand(const std::vector<std::string>& boxes, const session::SessionCase& scene, const session::SessionOptions& options) {
  std::vector<session::BoxBinding> bindings;
  for (const std::string& b : boxes) {
    const base::Result<session::BoxBinding> parsed = session::parse_box_binding(b, scene.spec.tools);
    if (!parsed) return {nullptr, kExitOk, parsed.error().message};
    for (const session::BoxBinding& other : bindings) {
      if (other.tool == parsed->tool) return {nullptr, kExitOk, "--box: two boxes for '" + parsed->tool_name + "'"};
    }
    bindings.push_back(*parsed);
  }
  session::BoxHandOptions rig_options;
  rig_options.emu_program = program_dir() + "/cathbox-emu";
  rig_options.dt_s = static_cast<double>(options.period_us) * 1e-6;
  base::Result<std::unique_ptr<session::MultiBoxHand>> rig = session::MultiBoxHand::connect(bindings, rig_options, scene.spec.tools.size());
  if (!rig) {
    std::fprintf(stderr, "cathbox session run: %s\n", rig.error().message.c_str());
    return {nullptr, kExitNoDevice, {}};
  }
  return {std::move(*rig), kExitOk, {}};
}

// Runs the session to its end: in virtual time (an action script) or real time (a box); an
// interrupt ends the run.
void drive(session::Session& s, bool virtual_time) {
  if (virtual_time) {
    while (!s.over()) {
      s.step_virtual(1000);
      print_events(s);
      if (g_interrupted.load()) s.end_run();
    }
    return;
  }
  s.start();
  while (!s.over()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    print_events(s);
    if (g_interrupted.load()) s.end_run();
  }
  s.stop();
}

}  // namespace

int run_run(Args& args, const GroupSpec& group) {
  // --emu takes an optional path: a bare --emu starts an emulator of its own.
  auto bad = [&](const std::string& what) { return usage_error(group, what, "session run"); };
  const auto seconds = args.number("seconds");
  if (!args.ok()) return bad(args.error());
  if (!args.positionals().empty()) return bad("unexpected argument '" + args.positionals()[0] + "'");
  const auto case_path = args.value("case");
  const auto script = args.value("script");
  const auto emu = args.value("emu");
  const std::vector<std::string> boxes = args.values("box");
  const auto record = args.value("record");
  if (!case_path || !record) return bad("--case and --record are required");
  if (static_cast<int>(script.has_value()) + static_cast<int>(emu.has_value()) + static_cast<int>(!boxes.empty()) != 1) {
    return bad("give one of --script ACTIONS, --emu [PATH] and --box TOOL=WHERE (repeated)");
  }
  if (boxes.size() == 1) return bad("--box needs two boxes or more (one box: --emu, which switches between tools)");
  if (seconds && (*seconds <= 0.0 || *seconds > 86'400.0)) return bad("--seconds must be in (0, 86400]");
  if ((emu || !boxes.empty()) && args.flag("virtual")) {
    return bad("--virtual runs an action script; the emulated box runs in real time (use --script for virtual time)");
  }

  session::SessionCaseLoad scene = session::load_session_case(*case_path);
  if (!scene) {
    std::fprintf(stderr, "%s\n", scene.error().message.c_str());
    return kExitBadInput;
  }
  session::SessionOptions options;
  if (seconds) options.max_ticks = static_cast<std::int64_t>(*seconds * 1e6 / static_cast<double>(options.period_us));
  HandChoice chosen;
  if (script) {
    chosen = script_hand(*script, *scene.value());
  } else if (emu) {
    chosen = emulator_hand(*emu, options);
  } else {
    chosen = box_rig_hand(boxes, *scene.value(), options);
    if (!chosen.usage_problem.empty()) return bad(chosen.usage_problem);
  }
  if (!chosen.hand) return chosen.exit_code;
  std::unique_ptr<session::Hand> hand = std::move(chosen.hand);
  session::Session s(std::move(scene.value()), std::move(hand), options);
  if (base::Status<> recording = s.record_to(*record); !recording) {
    std::fprintf(stderr, "%s\n", recording.error().message.c_str());
    return kExitBadInput;
  }
  session::ToolForces forces;
  if (args.flag("forces")) s.add_observer(forces);
  if (args.flag("progress")) {
    s.recorder()->on_block_written([](std::int64_t ticks, std::uint64_t bytes) {
      std::printf("recorded %lld ticks, %llu bytes\n", static_cast<long long>(ticks), static_cast<unsigned long long>(bytes));
      std::fflush(stdout);
    });
  }
  std::printf("cathbox session: %s, %s, %s -> %s\n", s.scene().name.c_str(), s.hand_description().c_str(),
              script ? "virtual time" : "real time", record->c_str());
  std::fflush(stdout);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  drive(s, script.has_value());
  print_events(s);
  session::Recorder& rec = *s.recorder();
  const bool written = rec.close();
  std::printf("end of run (%s): %lld ticks, %.3f s; record %s: %llu bytes\n%s",
              session::record::end_reason_name(s.end_reason()), static_cast<long long>(s.ticks()),
              static_cast<double>(s.ticks() * options.period_us) * 1e-6, record->c_str(),
              static_cast<unsigned long long>(rec.bytes_written()), session::MetricsCollector::format(s.metrics()).c_str());
  if (args.flag("forces")) std::printf("%s", forces.format().c_str());
  if (!written) {
    std::fprintf(stderr, "%s\n", rec.error().c_str());
    return kExitFailure;
  }
  return kExitOk;
}

}  // namespace cathbox::cli
