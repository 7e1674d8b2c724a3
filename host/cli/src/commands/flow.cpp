// `cathbox flow info CASE [--json]`: the blood-flow network of a case (sim/flow): flow, mean
// and peak velocity, Reynolds number and end pressures per segment, and what each free end
// does (inlet, outlet with its territory and target, closed sac). CASE is a case file (its
// `flow` overrides apply) or an HCLM file (defaults). Bad input: one line naming the file (and
// line), exit code 2.
#include <cstdio>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/args.hpp"
#include "cli/exit_codes.hpp"
#include "cli/registry.hpp"
#include "cli/usage.hpp"
#include "flow/flow_network.hpp"
#include "scenario/case_file.hpp"
#include "vessel/hclm.hpp"

namespace {

namespace cli = cathbox::cli;
namespace flow = cathbox::flow;
namespace vessel = cathbox::vessel;

// The group's command line, described once: parsing, help and the usage after an error.
const cli::GroupSpec& spec() {
  static const cli::GroupSpec group{
      .name = "flow",
      .summary = "blood flow network of a case: info (flow and velocity per segment)",
      .subcommands = {{.name = "info",
                       .positionals = "CASE",
                       .help = "flow, velocities, Reynolds number and pressures per segment; each free end's role (CASE: a .case or .hclm file)",
                       .options = {{.name = "json", .help = "print JSON (host/cli/README.md)"}}}},
  };
  return group;
}

int usage_error(const std::string& message) { return cli::usage_error(spec(), message); }

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

const char* role_name(flow::EndRole r) {
  switch (r) {
    case flow::EndRole::kInlet: return "inlet";
    case flow::EndRole::kOutlet: return "outlet";
    case flow::EndRole::kClosed: return "closed";
    case flow::EndRole::kJunction: return "junction";
  }
  return "junction";
}

// The case's vessel model and flow settings, or nullopt after printing the one-line error.
std::optional<std::pair<vessel::VesselModel, flow::FlowSettings>> load(const std::string& path) {
  std::string hclm_path = path;
  flow::FlowSettings settings;
  if (!ends_with(path, ".hclm")) {
    cathbox::tool::CaseParse parsed = cathbox::tool::load_case(path);
    if (!parsed) {
      std::fprintf(stderr, "%s\n", parsed.error().message.c_str());
      return std::nullopt;
    }
    if (parsed->vessel_path.empty()) {
      std::fprintf(stderr, "%s:0: the case has analytic tubes, not a vessel model: no flow network\n", path.c_str());
      return std::nullopt;
    }
    hclm_path = parsed->vessel_path;
    settings = parsed->flow;
  }
  vessel::HclmReadResult read = vessel::load_hclm(hclm_path);
  if (!read.ok()) {
    std::string line = read.errors.front().to_string();
    if (read.errors.size() > 1) line += " (+" + std::to_string(read.errors.size() - 1) + " more)";
    std::fprintf(stderr, "%s\n", line.c_str());
    return std::nullopt;
  }
  return std::make_pair(std::move(read.model), settings);
}

int run_info(const cli::Args& args) {
  if (args.positionals().size() != 1) return usage_error("info takes one CASE");
  const std::string& path = args.positionals()[0];
  const auto loaded = load(path);
  if (!loaded) return cli::kExitBadInput;
  const flow::FlowBuild built = flow::FlowNetwork::build(loaded->first, loaded->second);
  if (!built) {
    std::fprintf(stderr, "%s\n", built.error().message.c_str());
    return cli::kExitBadInput;
  }
  const flow::FlowNetwork& net = **built;
  const vessel::VesselModel& model = net.model();
  const flow::FlowSettings& s = net.settings();
  if (args.flag("json")) {
    nlohmann::ordered_json j;
    j["file"] = path;
    j["settings"] = {{"viscosity_mPa_s", s.viscosity_mPa_s},
                     {"cardiac_output_ml_min", s.cardiac_output_ml_min},
                     {"cerebral_fraction", s.cerebral_fraction},
                     {"arterial_pressure_mmHg", s.arterial_pressure_mmHg},
                     {"venous_pressure_mmHg", s.venous_pressure_mmHg},
                     {"wall_shear_stress_Pa", s.wall_shear_stress_Pa},
                     {"dispersion_radii", s.dispersion_radii},
                     {"sac_exchange_fraction", s.sac_exchange_fraction},
                     {"heart_rate_bpm", s.heart_rate_bpm},
                     {"pulsatility_index", s.pulsatility_index}};
    j["total_inflow_ml_min"] = net.total_inflow_ml_min();
    j["segments"] = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < model.segments.size(); ++i) {
      const flow::SegmentFlow& f = net.segments()[i];
      j["segments"].push_back({{"id", model.segments[i].id},
                               {"name", model.segments[i].name},
                               {"flow_ml_min", f.flow_ml_min()},
                               {"mean_velocity_mm_s", f.mean_velocity_mm_s},
                               {"peak_velocity_mm_s", f.peak_velocity_mm_s},
                               {"reynolds", f.reynolds},
                               {"length_mm", f.length_mm},
                               {"volume_ml", f.volume_mm3 * 1e-3},
                               {"resistance_Pa_s_per_mm3", f.resistance_Pa_s_per_mm3},
                               {"pressure_start_mmHg", net.node_pressure_mmHg(f.start_node)},
                               {"pressure_end_mmHg", net.node_pressure_mmHg(f.end_node)}});
    }
    j["terminals"] = nlohmann::ordered_json::array();
    for (const flow::Terminal& t : net.terminals()) {
      j["terminals"].push_back({{"segment_id", model.segments[t.segment].id},
                                {"end", t.at_end ? "distal" : "proximal"},
                                {"role", role_name(t.role)},
                                {"territory", std::string(flow::territory_label(t.territory))},
                                {"overridden", t.overridden},
                                {"target_ml_min", t.role == flow::EndRole::kClosed ? 0.0 : t.target_ml_min},
                                {"flow_ml_min", t.flow_ml_min}});
    }
    std::printf("%s\n", j.dump(2).c_str());
    return cli::kExitOk;
  }
  std::printf("file        %s\n", path.c_str());
  std::printf("blood       %.2f mPa.s, arterial %.0f / venous %.0f mmHg, cardiac output %.0f mL/min (%.0f %% to the brain)\n",
              s.viscosity_mPa_s, s.arterial_pressure_mmHg, s.venous_pressure_mmHg, s.cardiac_output_ml_min,
              100.0 * s.cerebral_fraction);
  std::printf("inflow      %.1f mL/min%s\n\n", net.total_inflow_ml_min(),
              s.heart_rate_bpm > 0.0 ? " (mean; pulsatile)" : "");
  std::printf("%6s  %-34s %10s %10s %10s %7s %8s %8s\n", "id", "segment", "mL/min", "v mm/s", "v_max", "Re", "p_in", "p_out");
  for (std::size_t i = 0; i < model.segments.size(); ++i) {
    const flow::SegmentFlow& f = net.segments()[i];
    std::printf("%6d  %-34.34s %10.2f %10.1f %10.1f %7.0f %8.2f %8.2f\n", model.segments[i].id, model.segments[i].name.c_str(),
                f.flow_ml_min(), f.mean_velocity_mm_s, f.peak_velocity_mm_s, f.reynolds, net.node_pressure_mmHg(f.start_node),
                net.node_pressure_mmHg(f.end_node));
  }
  std::printf("\n%6s  %-9s %-8s %-18s %12s %12s\n", "id", "end", "role", "territory", "target", "flow");
  for (const flow::Terminal& t : net.terminals()) {
    const bool closed = t.role == flow::EndRole::kClosed;
    std::printf("%6d  %-9s %-8s %-18s %12.2f %12.2f%s\n", model.segments[t.segment].id, t.at_end ? "distal" : "proximal",
                role_name(t.role), t.role != flow::EndRole::kOutlet ? "-" : std::string(flow::territory_label(t.territory)).c_str(),
                closed ? 0.0 : t.target_ml_min, t.flow_ml_min, t.overridden ? "  (case)" : "");
  }
  return cli::kExitOk;
}

int run_flow(std::span<const std::string> argv) {
  return cli::run_group(spec(), argv, [](std::string_view, cli::Args& args) { return run_info(args); });
}

const cli::Registrar registrar({spec().name, spec().summary, run_flow});

}  // namespace
