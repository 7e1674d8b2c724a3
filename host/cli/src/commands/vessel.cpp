// `cathbox vessel validate|info|mesh|import|generate`: the vessel model (HCLM) from the command line.
#include <algorithm>
#include <cmath>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include <malloc.h>

#include <nlohmann/json.hpp>

#include <glm/geometric.hpp>

#include "cli/args.hpp"
#include "cli/exit_codes.hpp"
#include "cli/registry.hpp"
#include "cli/usage.hpp"
#include "vessel/case_generator.hpp"
#include "vessel/control_mesh_builder.hpp"
#include "vessel/hclm.hpp"
#include "vessel/mesh_analysis.hpp"
#include "vessel/mesh_export.hpp"
#include "vessel/vessel_graph.hpp"
#include "vessel/vessel_mesher.hpp"
#include "vessel_import/importer.hpp"

namespace {

namespace cli = cathbox::cli;
namespace vessel = cathbox::vessel;
namespace vessel_import = cathbox::vessel_import;

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
                        {.name = "sac", .value = "X,Y,Z", .help = "the blind segment nearest this point (input units) is an aneurysm sac"},
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

// Reads and validates; on bad input prints one line: the first problem (and how many more).
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

// Meshing allocates and frees a few hundred bytes per output triangle in large blocks (the
// subdivision levels, then the mesh check's edge lists); glibc maps blocks over 128 KB-32 MB
// afresh and unmaps them when freed, so every one is faulted in page by page again (~1 us a
// page on a virtual machine, a quarter of the command's time at 7M triangles). Serving them
// from the heap and keeping freed memory for the next one faults each page in once.
// One arena for every thread, so that the check running beside the writer (run_mesh) reuses the
// subdivision's freed memory too instead of faulting in an arena of its own.
void keep_freed_memory() {
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  mallopt(M_ARENA_MAX, 1);
}

int run_mesh(cli::Args& args) {
  if (args.positionals().size() != 1) return usage_error("mesh takes one FILE");
  const auto output = args.value("output");
  if (!output) return usage_error("mesh needs -o OUT.obj|.ply|.stl|.cbxmesh");
  vessel::MeshOptions options;
  if (const auto m = args.integer("ring")) options.ring_points = static_cast<int>(*m);
  if (const auto l = args.integer("level")) options.subdivision_level = static_cast<int>(*l);
  if (const auto s = args.integer("smooth")) options.smoothing_passes = static_cast<int>(*s);
  if (!args.ok()) return usage_error(args.error());
  if (options.ring_points < 3 || options.ring_points > 64) return usage_error("--ring must be 3..64");
  if (options.subdivision_level < 0 || options.subdivision_level > 5) return usage_error("--level must be 0..5");
  if (options.smoothing_passes < 0 || options.smoothing_passes > 100) return usage_error("--smooth must be 0..100");
  if (const auto method = args.value("smoothing")) {
    if (*method == "taubin") options.smoothing = vessel::SmoothingMethod::kTaubin;
    else if (*method == "moving-average") options.smoothing = vessel::SmoothingMethod::kMovingAverage;
    else return usage_error("--smoothing must be taubin or moving-average");
  }
  if (const auto rings = args.value("rings")) {
    if (*rings == "adaptive") options.ring_placement = vessel::RingPlacement::kAdaptive;
    else if (*rings == "per-point") options.ring_placement = vessel::RingPlacement::kPerPoint;
    else return usage_error("--rings must be adaptive or per-point");
  }
  options.caps = !args.flag("no-caps");
  options.trim_at_junctions = !args.flag("no-trim");
  options.fit_junctions = !args.flag("no-junction-fit");
  options.junction_fallback = !args.flag("no-junction-fallback");
  if (args.flag("control-mesh")) options.subdivision_level = 0;
  const std::string& path = args.positionals()[0];
  const auto model = read_model(path);
  if (!model) return cli::kExitBadInput;
  keep_freed_memory();
  const vessel::VesselSurface surface = vessel::build_vessel_surface(*model, options);
  if (!surface.ok()) {
    std::fprintf(stderr, "%s: %s\n", path.c_str(), surface.error.c_str());
    return cli::kExitBadInput;
  }
  // The check (about a sixth of the command's CPU) runs on a second thread while this one writes
  // the file (its copy into the page cache is most of the writing): both only read the mesh.
  vessel::MeshAnalysis a;
  std::thread check([&a, &surface] { a = vessel::analyze_mesh(surface.mesh); });
  const std::string error = vessel::write_mesh(surface.mesh, *output);
  check.join();
  if (!error.empty()) {
    std::fprintf(stderr, "cathbox vessel mesh: %s\n", error.c_str());
    return error.rfind("unknown mesh format", 0) == 0 ? cli::kExitBadInput : cli::kExitFailure;
  }
  std::printf("%s: control mesh %zu vertices %zu faces; surface %zu vertices %zu triangles; euler %d; %s, %s; "
              "volume %.1f mm3\n",
              output->c_str(), surface.control.vertex_count(), surface.control.face_count(), a.vertices, a.triangles,
              a.euler_characteristic, a.closed() ? "closed" : "open", a.manifold() ? "manifold" : "NOT manifold",
              a.signed_volume_mm3);
  if (const std::string fallback = vessel::fallback_summary(surface.control); !fallback.empty()) {
    std::printf("%s: %s\n", output->c_str(), fallback.c_str());
  }
  return cli::kExitOk;
}

bool is_hclm_name(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext == ".hclm";
}

// `-o CASE_DIR`: the imported vessel as a case a session runs as it is: vessel.hclm (the graph),
// lumen.cbxmesh (a surface's repaired lumen, the case's wall) and NAME.case naming both.
int write_case_dir(const std::string& in, const std::filesystem::path& dir, const vessel_import::ImportResult& result,
                   std::string& case_path) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    std::fprintf(stderr, "cathbox vessel import: %s: cannot create the case folder (%s)\n", dir.string().c_str(), ec.message().c_str());
    return cli::kExitFailure;
  }
  const std::string name = std::filesystem::path(in).stem().string();
  std::string text = "cathbox-case 1\nname " + name + "\nvessel vessel.hclm\n";
  std::string error = vessel::save_hclm(result.model, (dir / "vessel.hclm").string());
  if (error.empty() && result.format == vessel_import::Format::kSurface) {
    text += "surface lumen.cbxmesh\n";
    error = vessel::write_mesh(result.lumen, (dir / "lumen.cbxmesh").string());
  }
  case_path = (dir / (name + ".case")).string();
  if (error.empty()) {
    std::ofstream out(case_path, std::ios::binary);
    if (!(out << text) || !out.flush()) error = case_path + ": cannot write";
  }
  if (!error.empty()) {
    std::fprintf(stderr, "cathbox vessel import: %s\n", error.c_str());
    return cli::kExitFailure;
  }
  return cli::kExitOk;
}

// `--surface-out FILE`: the repaired lumen, with either form of -o.
int write_surface_out(const std::string& path, const vessel_import::ImportResult& result) {
  if (const std::string error = vessel::write_mesh(result.lumen, path); !error.empty()) {
    std::fprintf(stderr, "cathbox vessel import: %s\n", error.c_str());
    return error.rfind("unknown mesh format", 0) == 0 ? cli::kExitBadInput : cli::kExitFailure;
  }
  return cli::kExitOk;
}

int run_import(cli::Args& args) {
  if (args.positionals().size() != 1) return usage_error("import takes one IN file");
  const auto output = args.value("output");
  if (!output) return usage_error("import needs -o OUT.hclm");
  vessel_import::ImportOptions options;
  if (const auto format = args.value("format")) {
    options.format = vessel_import::format_from_name(*format);
    if (!options.format) return usage_error("--format must be vtk, vtp, slicer, swc or surface");
  }
  if (const auto units = args.value("units")) {
    const auto mm = vessel_import::unit_to_mm(*units);
    if (!mm) return usage_error("--units must be mm, cm, m or um");
    options.unit_mm = *mm;
  }
  if (const auto name = args.value("radius-array")) options.radius_array = *name;
  options.filter_radii = !args.flag("no-radius-filter");
  options.keep_largest = args.flag("largest");
  const auto inlet = args.numbers("inlet", 3);
  const auto sac = args.numbers("sac", 3);
  if (!args.ok()) return usage_error(args.error());
  if (inlet) options.inlet = glm::dvec3((*inlet)[0], (*inlet)[1], (*inlet)[2]);
  if (sac) options.sac = glm::dvec3((*sac)[0], (*sac)[1], (*sac)[2]);
  const std::string& path = args.positionals()[0];
  const vessel_import::ImportResult result = vessel_import::import_centerlines(path, options);
  if (!result.ok()) {
    std::string line = result.errors.front().to_string();
    if (result.errors.size() > 1) line += " (+" + std::to_string(result.errors.size() - 1) + " more)";
    std::fprintf(stderr, "%s\n", line.c_str());
    return cli::kExitBadInput;
  }
  const auto lumen = args.value("surface-out");
  if (lumen && result.format != vessel_import::Format::kSurface) return usage_error("--surface-out needs a surface to import");
  const std::filesystem::path out_path(*output);
  std::string written = *output;
  if (!is_hclm_name(out_path)) {
    if (const int rc = write_case_dir(path, out_path, result, written); rc != cli::kExitOk) return rc;
  } else if (const std::string error = vessel::save_hclm(result.model, *output); !error.empty()) {
    std::fprintf(stderr, "cathbox vessel import: %s\n", error.c_str());
    return cli::kExitFailure;
  }
  if (lumen) {
    if (const int rc = write_surface_out(*lumen, result); rc != cli::kExitOk) return rc;
  }
  std::printf("%s: %s\n", written.c_str(), result.summary().c_str());
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
    if (sub == "mesh") return run_mesh(args);
    if (sub == "import") return run_import(args);
    return run_generate(args);
  });
}

const cli::Registrar registrar({spec().name, spec().summary, run_vessel});

}  // namespace
