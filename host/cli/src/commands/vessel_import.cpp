// `cathbox vessel import`: centrelines or a surface to HCLM or a case folder (vessel.cpp has the group).
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <glm/vec3.hpp>

#include "cli/args.hpp"
#include "cli/exit_codes.hpp"
#include "cli/usage.hpp"
#include "vessel/hclm.hpp"
#include "vessel/mesh_export.hpp"
#include "vessel_commands.hpp"
#include "vessel_import/importer.hpp"

namespace cathbox::cli {
namespace {

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

}  // namespace

int run_import(cli::Args& args, const cli::GroupSpec& group) {
  const auto usage_error = [&](const std::string& what) { return cli::usage_error(group, what); };
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
  if (sac && !inlet) return usage_error(vessel_import::kSacNeedsInlet);
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

}  // namespace cathbox::cli
