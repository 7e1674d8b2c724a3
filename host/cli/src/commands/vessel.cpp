// `cathbox vessel validate|info|mesh|import|generate`: the vessel model (HCLM) from the command line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <glm/geometric.hpp>

#include "cli/args.hpp"
#include "cli/exit_codes.hpp"
#include "cli/registry.hpp"
#include "cli/usage.hpp"
#include "vessel/case_generator.hpp"
#include "vessel/hclm.hpp"
#include "vessel/vessel_graph.hpp"
#include "vessel_commands.hpp"

namespace cathbox::cli {

std::optional<vessel::VesselModel> read_model(const std::string& path) {
  vessel::HclmReadResult read = vessel::load_hclm(path);
  if (!read.ok()) {
    std::string line = read.errors.front().to_string();
    if (read.errors.size() > 1) line += " (+" + std::to_string(read.errors.size() - 1) + " more)";
    std::fprintf(stderr, "%s\n", line.c_str());
    return std::nullopt;
  }
  return std::move(read.model);
}

}  // namespace cathbox::cli

namespace {

namespace cli = cathbox::cli;
namespace vessel = cathbox::vessel;
using cli::read_model;

// The group's command line, described once: parsing, help and the usage after an error.
const cli::GroupSpec& spec() {
  static const cli::GroupSpec group{
      .name = "vessel",
      .summary = "vessel models: validate, info, mesh, import, generate (HCLM)",
      .subcommands =
          {{.name = "validate", .positionals = "FILE", .help = "reads and validates an HCLM file"},
           {.name = "info",
            .positionals = "FILE",
            .help = "segments, points, junctions, cycles, length and radii",
            .options = {{.name = "json", .help = "print JSON (host/cli/README.md)"}}},
           {.name = "mesh",
            .positionals = "FILE",
            .help = "meshes the vessel surface to .obj, .ply, .stl or .cbxmesh (the exact bytes the WebAssembly session builds its collision tree from)",
            .options = {{.name = "output", .value = "OUT.obj|.ply|.stl|.cbxmesh", .help = "the mesh file", .required = true, .short_name = 'o'},
                        {.name = "ring", .value = "M", .help = "points per ring, 3..64"},
                        {.name = "level", .value = "L", .help = "subdivision level, 0..5"},
                        {.name = "control-mesh", .help = "write the control mesh (level 0)"},
                        {.name = "no-caps", .help = "leave the free ends open"},
                        {.name = "no-trim", .help = "do not pull rings back at junctions"},
                        {.name = "smooth", .value = "N", .help = "smoothing passes, 0..100"},
                        {.name = "smoothing", .value = "taubin|moving-average", .help = "smoothing method"},
                        {.name = "rings", .value = "adaptive|per-point", .help = "ring placement"},
                        {.name = "no-junction-fit", .help = "do not fit junction patches to their branches"},
                        {.name = "no-junction-fallback",
                         .help = "refuse a junction whose branches overlap instead of meshing it by the spherical-hull fallback"}}},
           {.name = "import",
            .positionals = "IN",
            .help = "centrelines from VMTK, 3D Slicer or SWC, or a vessel surface (STL, OBJ, PLY, OFF), to HCLM",
            .options = {{.name = "output",
                         .value = "OUT.hclm|CASE_DIR",
                         .help = "the HCLM file, or a folder to hold a case: vessel.hclm, lumen.cbxmesh (a surface: the case's wall) and NAME.case",
                         .required = true,
                         .short_name = 'o'},
                        {.name = "format", .value = "vtk|vtp|slicer|swc|surface", .help = "input format (default: from the name)"},
                        {.name = "largest", .help = "a surface in several pieces: keep the largest"},
                        {.name = "surface-out", .value = "FILE", .help = "a surface: write the repaired lumen (.obj, .ply, .stl, .cbxmesh)"},
                        {.name = "units", .value = "mm|cm|m|um", .help = "the input's length unit"},
                        {.name = "radius-array", .value = "NAME", .help = "the point array holding the radius"},
                        {.name = "inlet", .value = "X,Y,Z", .help = "the free end nearest this point (input units) is the inlet; default: the widest"},
                        {.name = "sac", .value = "X,Y,Z", .help = "the blind segment nearest this point (input units) is an aneurysm sac; needs --inlet"},
                        {.name = "no-radius-filter", .help = "keep radii as read"}}},
           {.name = "generate",
            .positionals = "NAME",
            .help = "a bundled or random case (NAME: neuro, neuro_aneurysm, neuro_small_aneurysm, neuro_stenosis, "
                    "y_bifurcation, random-tree, random-graph)",
            .options = {{.name = "output", .value = "OUT.hclm", .help = "the HCLM file", .required = true, .short_name = 'o'},
                        {.name = "all", .value = "DIR", .help = "all bundled cases into DIR (instead of NAME and -o)"},
                        {.name = "seed", .value = "S", .help = "random-tree / random-graph seed"},
                        {.name = "segments", .value = "N", .help = "random-tree segments, 1..100000"},
                        {.name = "cycles", .value = "C", .help = "random-graph cycles, 1..8"}}}},
      .notes = "generate: NAME -o OUT.hclm, or --all DIR alone; --seed and --segments for random-tree, --seed and "
               "--cycles for random-graph",
  };
  return group;
}

int usage_error(const std::string& message) { return cli::usage_error(spec(), message); }

int run_validate(const cli::Args& args) {
  if (args.positionals().size() != 1) return usage_error("validate takes one FILE");
  const std::string& path = args.positionals()[0];
  const auto model = read_model(path);
  if (!model) return cli::kExitBadInput;
  std::printf("%s: ok (%zu segments, %zu points)\n", path.c_str(), model->segments.size(), model->point_count());
  return cli::kExitOk;
}

std::string junction_kind(const vessel::Junction& j) {
  const auto parents = static_cast<int>(std::count_if(j.ends.begin(), j.ends.end(), [](auto& e) { return e.at_end; }));
  const int children = static_cast<int>(j.ends.size()) - parents;
  if (parents == 1 && children == 1) return "continuation";
  if (parents == 1 && children == 2) return "bifurcation";
  if (parents == 1 && children == 3) return "trifurcation";
  if (parents >= 2 && children == 1) return "confluence";
  return "junction_" + std::to_string(parents) + "_" + std::to_string(children);
}

int run_info(const cli::Args& args) {
  if (args.positionals().size() != 1) return usage_error("info takes one FILE");
  const std::string& path = args.positionals()[0];
  const auto model = read_model(path);
  if (!model) return cli::kExitBadInput;
  const vessel::VesselGraph graph(*model);
  double length_mm = 0.0;
  double r_min = std::numeric_limits<double>::infinity();
  double r_max = 0.0;
  for (const vessel::Segment& s : model->segments) {
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      if (i > 0) length_mm += glm::length(s.points[i].pos_mm - s.points[i - 1].pos_mm);
      r_min = std::min(r_min, s.points[i].radius_mm);
      r_max = std::max(r_max, s.points[i].radius_mm);
    }
  }
  std::vector<std::pair<std::string, int>> kinds;
  for (const vessel::Junction& j : graph.junctions()) {
    const std::string kind = junction_kind(j);
    auto it = std::find_if(kinds.begin(), kinds.end(), [&](auto& k) { return k.first == kind; });
    if (it == kinds.end()) kinds.emplace_back(kind, 1);
    else ++it->second;
  }
  if (args.flag("json")) {
    nlohmann::ordered_json j;
    j["file"] = path;
    j["segments"] = model->segments.size();
    j["points"] = model->point_count();
    j["junctions"] = graph.junctions().size();
    j["junction_kinds"] = nlohmann::ordered_json::object();
    for (const auto& [kind, count] : kinds) j["junction_kinds"][kind] = count;
    j["free_ends"] = graph.free_ends().size();
    j["components"] = graph.component_count();
    j["cycles"] = graph.cycle_count();
    j["total_length_mm"] = length_mm;
    j["radius_min_mm"] = std::isfinite(r_min) ? r_min : 0.0;  // 0 for a model without points
    j["radius_max_mm"] = std::isfinite(r_max) ? r_max : 0.0;
    std::printf("%s\n", j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace).c_str());
    return cli::kExitOk;
  }
  std::printf("file          %s\n", path.c_str());
  std::printf("segments      %zu (%zu points)\n", model->segments.size(), model->point_count());
  std::printf("junctions     %zu", graph.junctions().size());
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    std::printf("%s%d %s", i ? ", " : " (", kinds[i].second, kinds[i].first.c_str());
  }
  std::printf("%s\n", kinds.empty() ? "" : ")");
  std::printf("free ends     %zu\n", graph.free_ends().size());
  std::printf("components    %d\n", graph.component_count());
  std::printf("cycles        %d\n", graph.cycle_count());
  std::printf("total length  %.1f mm\n", length_mm);
  std::printf("radius        %.3g .. %.3g mm\n", r_min, r_max);
  return cli::kExitOk;
}

int save(const vessel::VesselModel& model, const std::string& path) {
  if (const std::string error = vessel::save_hclm(model, path); !error.empty()) {
    std::fprintf(stderr, "cathbox vessel generate: %s\n", error.c_str());
    return cli::kExitFailure;
  }
  std::printf("%s: %zu segments, %zu points\n", path.c_str(), model.segments.size(), model.point_count());
  return cli::kExitOk;
}

int run_generate(cli::Args& args) {
  if (const auto dir = args.value("all")) {
    if (!args.positionals().empty()) return usage_error("generate --all DIR takes no NAME");
    std::error_code ec;
    std::filesystem::create_directories(*dir, ec);
    for (const std::string& name : vessel::CaseGenerator::case_names()) {
      const int rc = save(vessel::CaseGenerator::make_case(name), (std::filesystem::path(*dir) / (name + ".hclm")).string());
      if (rc != cli::kExitOk) return rc;
    }
    return cli::kExitOk;
  }
  if (args.positionals().size() != 1) return usage_error("generate takes one NAME (or --all DIR)");
  const auto output = args.value("output");
  if (!output) return usage_error("generate needs -o OUT.hclm");
  const std::string& name = args.positionals()[0];
  const auto seed = args.integer("seed");
  const auto segments = args.integer("segments");
  const auto cycles = args.integer("cycles");
  if (!args.ok()) return usage_error(args.error());
  if (name == "random-tree") {
    vessel::RandomTreeOptions options;
    if (segments) {
      if (*segments < 1 || *segments > 100000) return usage_error("--segments must be 1..100000");
      options.segments = static_cast<int>(*segments);
    }
    return save(vessel::CaseGenerator::random_tree(static_cast<std::uint64_t>(seed.value_or(1)), options), *output);
  }
  if (name == "random-graph") {
    const long long c = cycles.value_or(1);
    if (c < 1 || c > 8) return usage_error("--cycles must be 1..8");
    return save(vessel::CaseGenerator::random_graph(static_cast<std::uint64_t>(seed.value_or(1)), static_cast<int>(c)),
                *output);
  }
  const vessel::VesselModel model = vessel::CaseGenerator::make_case(name);
  if (model.segments.empty()) return usage_error("unknown case '" + name + "'");
  return save(model, *output);
}

int run_vessel(std::span<const std::string> argv) {
  return cli::run_group(spec(), argv, [](std::string_view sub, cli::Args& args) {
    if (sub == "validate") return run_validate(args);
    if (sub == "info") return run_info(args);
    if (sub == "mesh") return cli::run_mesh(args, spec());
    if (sub == "import") return cli::run_import(args, spec());
    return run_generate(args);
  });
}

const cli::Registrar registrar({spec().name, spec().summary, run_vessel});

}  // namespace
