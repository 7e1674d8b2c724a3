// `cathbox sim`: the tool simulator without GUI and without a box (command line: spec() below).
// FILE is a case file (sim/tool/README.md) or an HCLM vessel (entry at the start of the root
// segment, default guidewire). Bad input: one line with file:line on stderr, exit code 2.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <optional>
#include <string>

#include "cli/args.hpp"
#include "cli/exit_codes.hpp"
#include "cli/registry.hpp"
#include "cli/usage.hpp"
#include "scenario/action_script.hpp"
#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"
#include "scenario/scenario_runner.hpp"
#include "tool/angioplasty.hpp"
#include "scenario/case_wall.hpp"
#include "tool/simulator.hpp"

namespace {

using cathbox::cli::kExitBadInput;
using cathbox::cli::kExitFailure;
using cathbox::cli::kExitOk;

// The group's command line, described once: parsing, help and the usage after an error.
const cathbox::cli::GroupSpec& spec() {
  static const cathbox::cli::GroupSpec group{
      .name = "sim",
      .summary = "run tool scenarios headless (sim run)",
      .subcommands = {{.name = "run",
                       .help = "a tool scenario in virtual time, logged per step (tip, force, torque)",
                       .options = {{.name = "case", .value = "FILE", .help = "a case file or an HCLM vessel", .required = true},
                                   {.name = "script", .value = "ACTIONS", .help = "the action script", .required = true},
                                   {.name = "out", .value = "LOG.csv", .help = "the log to write", .required = true},
                                   {.name = "every", .value = "MS", .help = "a row every MS ms (default 1)"}}}},
  };
  return group;
}

// The balloon's figures, one per line (host/cli/README.md).
void print_coils(const cathbox::tool::CoilFigures& c, double sac_volume_mm3) {
  std::printf("coil: %.1f mm deployed, packing density %.1f %% of a %.1f mm3 sac, %d herniations, kick-back %.2f mm\n",
              c.deployed_mm, 100.0 * c.packing_density, sac_volume_mm3, c.herniations, c.kick_back_mm);
  if (c.herniations > 0)
    std::printf("coil herniated: up to %d nodes at once, %.2f mm past the neck plane\n", c.herniated_peak_nodes,
                c.herniated_depth_mm);
  if (c.detachments == 0) return;
  std::printf("coil detach force:");
  const int kept = std::min(c.detachments, static_cast<int>(cathbox::tool::CoilFigures::kMaxDetachments));
  for (int i = 0; i < kept; ++i) std::printf("%s %+.1f", i == 0 ? "" : ",", c.detach_force_mN[static_cast<std::size_t>(i)]);
  std::printf(" mN (%d under tension)\n", c.detached_under_tension);
}

void print_angioplasty(const cathbox::tool::AngioplastyFigures& f) {
  if (f.lesion) {
    std::printf("stenosis before: %.1f %%, residual stenosis: %.1f %% (reference %.2f mm)\n", f.stenosis_before_percent,
                f.residual_stenosis_percent, f.reference_diameter_mm);
  } else {
    std::printf("stenosis: none found in the vessel\n");
  }
  std::printf("balloon: %d inflation(s), %.2f s inflated, max %.1f atm%s; rupture-risk events: %d (largest %.2fx reference)\n",
              f.inflations, f.inflated_time_s, f.max_pressure_atm, f.over_rated_burst ? " (over rated burst)" : "",
              f.rupture_risk_events, f.max_oversize_ratio);
  std::printf("wall swaps: %llu, of which waited for the builder: %llu\n", static_cast<unsigned long long>(f.wall_swaps),
              static_cast<unsigned long long>(f.swap_waits));
}

int usage_error(const std::string& message) { return cathbox::cli::usage_error(spec(), message, "sim run"); }

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

int run_run(cathbox::cli::Args& args) {
  if (!args.positionals().empty()) return usage_error("unexpected argument");
  const auto case_path = args.value("case");
  const auto script_path = args.value("script");
  const auto out_path = args.value("out");
  if (!case_path || !script_path || !out_path) return usage_error("--case, --script and --out are required");
  long long every = 1;
  if (args.value("every")) {
    const auto v = args.integer("every");
    if (!v || *v < 1 || *v > 3600000) {
      std::fprintf(stderr, "cathbox sim run: --every must be a whole number of milliseconds >= 1\n");
      return kExitBadInput;
    }
    every = *v;
  }
  cathbox::tool::Case scenario_case;
  if (ends_with(*case_path, ".hclm")) {
    scenario_case.vessel_path = *case_path;
    scenario_case.tools.push_back(cathbox::tool::default_guidewire());
  } else {
    cathbox::tool::CaseParse parsed = cathbox::tool::load_case(*case_path);
    if (!parsed) {
      std::fprintf(stderr, "%s\n", parsed.error().message.c_str());
      return kExitBadInput;
    }
    scenario_case = std::move(*parsed);
  }
  const cathbox::tool::ScriptParse script = cathbox::tool::load_script(*script_path);
  if (!script) {
    std::fprintf(stderr, "%s\n", script.error().message.c_str());
    return kExitBadInput;
  }
  cathbox::tool::WorldBuild world = cathbox::tool::build_world(scenario_case);
  if (!world) {
    std::fprintf(stderr, "%s\n", world.error().message.c_str());
    return kExitBadInput;
  }
  // A balloon catheter in a meshed vessel: the lumen it widens gets new walls (synchronous:
  // headless runs give the same log on every machine).
  std::optional<cathbox::tool::Angioplasty> angioplasty;
  const bool balloon = std::any_of(scenario_case.tools.begin(), scenario_case.tools.end(),
                                   [](const cathbox::tool::ToolSpec& t) { return t.balloon.present(); });
  if (balloon && (*world)->source_model() != nullptr) {
    angioplasty.emplace(*(*world)->source_model(), (*world)->release_wall(), cathbox::tool::WallSwap::Mode::kSynchronous);
  }
  cathbox::tool::Simulator sim(angioplasty ? angioplasty->wall() : (*world)->wall(), scenario_case.tools, (*world)->entry());
  cathbox::tool::use_case_wall(sim, scenario_case.wall ? &*scenario_case.wall : nullptr, (*world)->source_model());  // a compliant wall
  std::ofstream out(*out_path, std::ios::binary | std::ios::trunc);
  if (!out) {
    std::fprintf(stderr, "%s: cannot open for writing\n", out_path->c_str());
    return kExitBadInput;
  }
  cathbox::tool::ScenarioOptions options;
  options.every_ms = every;
  options.script_name = *script_path;
  if ((*world)->sac()) options.sac = &*(*world)->sac();
  options.angioplasty = angioplasty ? &*angioplasty : nullptr;
  const cathbox::tool::ScenarioResult result = cathbox::tool::run_scenario(sim, *script, options, out);
  if (!result.ok) {
    std::fprintf(stderr, "%s\n", result.error.c_str());
    out.close();
    std::remove(out_path->c_str());
    return kExitBadInput;
  }
  out.close();
  if (!out) {
    std::fprintf(stderr, "%s: write failed\n", out_path->c_str());
    return kExitFailure;
  }
  std::printf("%llu steps, %llu rows -> %s\n", static_cast<unsigned long long>(result.steps),
              static_cast<unsigned long long>(result.rows), out_path->c_str());
  for (const std::string& note : result.notes) std::fprintf(stderr, "%s\n", note.c_str());
  if (result.coils) print_coils(*result.coils, options.sac->volume_mm3);
  if (result.angioplasty) print_angioplasty(*result.angioplasty);
  return kExitOk;
}

int run_sim(std::span<const std::string> argv) {
  return cathbox::cli::run_group(spec(), argv, [](std::string_view, cathbox::cli::Args& args) { return run_run(args); });
}

const cathbox::cli::Registrar registrar({spec().name, spec().summary, run_sim});

}  // namespace
