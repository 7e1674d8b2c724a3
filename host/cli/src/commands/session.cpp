// `cathbox session`: a haptic session without the trainer's window (host/session), and what a
// record holds (host/cli/README.md documents the --json shapes). The command line is spec() below.
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "cli/args.hpp"
#include "cli/exit_codes.hpp"
#include "cli/registry.hpp"
#include "cli/usage.hpp"
#include "session_json.hpp"
#include "session_run.hpp"
#include "session/record_reader.hpp"
#include "session/replay.hpp"
#include "session/tool_forces.hpp"
#include "session/tool_trace.hpp"
#include "scenario/scenario_runner.hpp"

namespace cathbox::cli {
namespace {

// The group's command line, described once: parsing, help and the usage after an error.
const GroupSpec& spec() {
  const OptionSpec json{.name = "json", .help = "print JSON (host/cli/README.md)"};
  static const GroupSpec group{
      .name = "session",
      .summary = "headless sessions and their records (session run|replay|metrics|info)",
      .subcommands =
          {{.name = "run",
            .help = "a headless session, recorded; driven by an action script (virtual time) or the emulated box",
            .options = {{.name = "case", .value = "FILE", .help = "the case (.case or .hclm)", .required = true},
                        {.name = "script", .value = "ACTIONS", .help = "drive it with an action script (or --emu)"},
                        {.name = "emu", .value = "[PATH]", .help = "drive it with cathbox-emu at PATH; alone: start one (or --script)"},
                        {.name = "box", .value = "TOOL=WHERE",
                         .help = "a box per tool, repeated (two or more): WHERE is a real box's serial, emu (start one) or emu:PATH"},
                        {.name = "record", .value = "OUT.cbxrec", .help = "the record to write", .required = true},
                        {.name = "seconds", .value = "S", .help = "end after S seconds, (0, 86400]"},
                        {.name = "virtual", .help = "virtual time (--script's only mode)"},
                        {.name = "progress", .help = "a line per block written"},
                        {.name = "forces", .help = "after the run, every tool's hand force against the box's slew and full scale (as replay --forces)"}}},
           {.name = "replay",
            .positionals = "REC",
            .help = "replays the record on a fresh simulator",
            .options = {{.name = "check", .help = "exit 1 at the first state hash that differs"},
                        {.name = "out", .value = "LOG.csv", .help = "log the held tool in cathbox sim run's columns"},
                        {.name = "every", .value = "MS", .help = "with --out: a row every MS ms"},
                        {.name = "forces",
                         .help = "print every tool's peak hand force, largest change a tick and ticks over the box's slew and full scale"},
                        {.name = "trace", .value = "FROM-TO",
                         .help = "print every tool's force, solve, tip and contacts at each tick from FROM to TO s"}}},
           {.name = "metrics", .positionals = "REC", .help = "replays (hash-checked) and prints every metric", .options = {json}},
           {.name = "info", .positionals = "REC", .help = "the record's header and what its ticks hold", .options = {json}}},
  };
  return group;
}

int usage_error(const std::string& what) { return cli::usage_error(spec(), what); }

// `cathbox session replay --out`: the `cathbox sim run` log of the held tool every MS ms.
class CsvLog final : public session::TickObserver {
 public:
  CsvLog(std::ostream& out, std::int64_t every_ms, std::int64_t period_us) : out_(out), every_(every_ms), period_us_(period_us) {
    tool::write_scenario_header(out_);
  }
  void observe(const session::TickView& v) override {
    const std::int64_t time_us = (v.tick + 1) * period_us_;
    if (time_us % 1000 != 0) return;
    const std::int64_t ms = time_us / 1000;
    if (ms % every_ == 0) tool::write_scenario_row(out_, v.sim, ms);
  }

 private:
  std::ostream& out_;
  std::int64_t every_;
  std::int64_t period_us_;
};

int run_replay(Args& args) {
  if (args.positionals().size() != 1) return usage_error("replay takes one record file");
  long long every = 1;
  if (args.value("every")) {
    const auto v = args.integer("every");
    if (!v || *v < 1 || *v > 3'600'000) return usage_error("--every must be a whole number of milliseconds >= 1");
    every = *v;
  }
  if (args.value("every") && !args.value("out")) return usage_error("--every needs --out");
  std::optional<session::ToolTrace> trace;
  if (args.value("trace")) {
    const std::optional<std::vector<double>> w = args.numbers("trace", 2, '-');
    if (!w || (*w)[0] < 0.0 || (*w)[1] < (*w)[0] || (*w)[1] > 1e6) {
      return usage_error("--trace must be FROM-TO in seconds, 0 <= FROM <= TO (e.g. 12.5-12.6)");
    }
    trace.emplace(std::llround((*w)[0] * 1e6), std::llround((*w)[1] * 1e6), stdout);
  }
  const std::string& path = args.positionals()[0];
  const bool check = args.flag("check");
  base::Result<std::unique_ptr<session::Replay>> opened = session::Replay::open(path, check);
  if (!opened) {
    std::fprintf(stderr, "%s\n", opened.error().message.c_str());
    return kExitBadInput;
  }
  std::unique_ptr<session::Replay> replay = std::move(*opened);
  std::ofstream csv;
  std::unique_ptr<CsvLog> log;
  if (const auto out = args.value("out")) {
    csv.open(*out, std::ios::binary | std::ios::trunc);
    if (!csv) {
      std::fprintf(stderr, "%s: cannot open for writing\n", out->c_str());
      return kExitBadInput;
    }
    log = std::make_unique<CsvLog>(csv, every, replay->header().period_us);
    replay->session().add_observer(*log);
  }
  session::ToolForces forces;
  if (args.flag("forces")) replay->session().add_observer(forces);
  if (trace) replay->session().add_observer(*trace);
  replay->step(-1);
  const session::ReplayResult r = replay->result();
  if (csv.is_open()) {
    csv.close();
    if (!csv) {
      std::fprintf(stderr, "%s: write failed\n", args.value("out")->c_str());
      return kExitFailure;
    }
  }
  const auto print_mismatch = [&] {
    std::printf("state hash differs at tick %lld (%.3f s): recorded %016llx, replayed %016llx\n",
                static_cast<long long>(r.mismatch->tick),
                static_cast<double>((r.mismatch->tick + 1) * replay->header().period_us) * 1e-6,
                static_cast<unsigned long long>(r.mismatch->recorded), static_cast<unsigned long long>(r.mismatch->replayed));
  };
  // --check stops at the first differing hash: the reader is then short of the end block by
  // design, so the tick counts and the "no end block" line would only mislead.
  if (check && r.mismatch && r.error.empty()) {
    print_mismatch();
    return kExitFailure;
  }
  std::printf("%s: replayed %lld of %lld recorded ticks, %lld state hashes checked\n", path.c_str(),
              static_cast<long long>(r.ticks), static_cast<long long>(r.recorded_ticks),
              static_cast<long long>(r.hashes_checked));
  if (!r.end && r.error.empty()) std::printf("the record has no end block: the recording process stopped (killed?)\n");
  if (args.flag("forces")) std::printf("%s", forces.format().c_str());
  if (r.mismatch) print_mismatch();
  if (!r.error.empty()) {
    std::fprintf(stderr, "%s\n", r.error.c_str());
    return kExitBadInput;
  }
  if (r.mismatch) return check ? kExitFailure : kExitOk;
  if (check) std::printf("every state hash matches\n");
  return kExitOk;
}

int run_metrics(const Args& args) {
  if (args.positionals().size() != 1) return usage_error("metrics takes one record file");
  const std::string& path = args.positionals()[0];
  const session::ReplayResult r = session::replay_record(path);
  if (!r.error.empty()) {
    std::fprintf(stderr, "%s\n", r.error.c_str());
    return kExitBadInput;
  }
  if (r.mismatch) {
    std::fprintf(stderr, "%s: the record does not replay (state hash differs at tick %lld): no metrics\n", path.c_str(),
                 static_cast<long long>(r.mismatch->tick));
    return kExitFailure;
  }
  if (args.flag("json")) {
    std::printf("%s\n", metrics_json(r).dump(2).c_str());
  } else {
    std::printf("%s", session::MetricsCollector::format(r.metrics).c_str());
  }
  return kExitOk;
}

int run_info(const Args& args) {
  if (args.positionals().size() != 1) return usage_error("info takes one record file");
  const std::string& path = args.positionals()[0];
  base::Result<std::unique_ptr<session::RecordReader>> opened = session::RecordReader::open(path);
  if (!opened) {
    std::fprintf(stderr, "%s\n", opened.error().message.c_str());
    return kExitBadInput;
  }
  std::unique_ptr<session::RecordReader> reader = std::move(*opened);
  const RecordSummary summary = summarise(*reader);
  if (args.flag("json")) {
    std::printf("%s\n", info_json(path, *reader, summary).dump(2).c_str());
  } else {
    std::printf("%s", info_text(path, *reader, summary).c_str());
  }
  if (!reader->error().empty()) {
    std::fprintf(stderr, "%s\n", reader->error().c_str());
    return kExitBadInput;
  }
  return kExitOk;
}

int run_session(std::span<const std::string> argv) {
  return run_group(spec(), argv, [](std::string_view sub, Args& args) {
    if (sub == "run") return run_run(args, spec());
    if (sub == "replay") return run_replay(args);
    if (sub == "metrics") return run_metrics(args);
    return run_info(args);
  });
}

const Registrar registrar({spec().name, spec().summary, run_session});

}  // namespace
}  // namespace cathbox::cli
