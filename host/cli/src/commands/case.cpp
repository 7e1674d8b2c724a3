// `cathbox case generate|list`: the case library by morphology (cases/library/): an HCLM, a .case
// and an .actions script per case.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli/args.hpp"
#include "cli/exit_codes.hpp"
#include "cli/registry.hpp"
#include "cli/usage.hpp"
#include "vessel/case_library.hpp"
#include "vessel/hclm.hpp"

namespace {

namespace cli = cathbox::cli;
namespace vessel = cathbox::vessel;

const cli::GroupSpec& spec() {
  static const cli::GroupSpec group{
      .name = "case",
      .summary = "the case library by morphology: arch types, ICA tortuosity, aneurysm sites",
      .subcommands =
          {{.name = "list", .help = "names of the library cases"},
           {.name = "generate",
            .positionals = "NAME",
            .help = "writes NAME.hclm, NAME.case and NAME.actions into DIR",
            .options = {{.name = "output", .value = "DIR", .help = "the directory", .short_name = 'o'},
                        {.name = "all", .value = "DIR", .help = "every library case into DIR (instead of NAME and -o)"}}}},
      .notes = "generate: NAME -o DIR, or --all DIR alone (the bundled copies: --all cases/library)",
  };
  return group;
}

int usage_error(const std::string& message) { return cli::usage_error(spec(), message); }

int write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) {
    std::fprintf(stderr, "cathbox case generate: cannot write %s\n", path.string().c_str());
    return cli::kExitFailure;
  }
  return cli::kExitOk;
}

int generate(const vessel::LibraryCase& c, const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  const vessel::VesselModel model = vessel::library_model(c);
  const std::string case_text = vessel::library_case_text(c, model);
  if (case_text.empty()) {
    std::fprintf(stderr, "cathbox case generate: %s: entry or target segment missing from the model\n", c.name.c_str());
    return cli::kExitFailure;
  }
  const std::filesystem::path hclm = dir / (c.name + ".hclm");
  if (const std::string error = vessel::save_hclm(model, hclm.string()); !error.empty()) {
    std::fprintf(stderr, "cathbox case generate: %s\n", error.c_str());
    return cli::kExitFailure;
  }
  if (const int rc = write_text(dir / (c.name + ".case"), case_text); rc != cli::kExitOk) return rc;
  if (const int rc = write_text(dir / (c.name + ".actions"), c.actions); rc != cli::kExitOk) return rc;
  std::printf("%s: %zu segments, %zu points, .case, .actions\n", hclm.string().c_str(), model.segments.size(),
              model.point_count());
  return cli::kExitOk;
}

int run_generate(cli::Args& args) {
  if (const auto dir = args.value("all")) {
    if (!args.positionals().empty()) return usage_error("generate --all DIR takes no NAME");
    for (const std::string& name : vessel::library_case_names()) {
      if (const int rc = generate(*vessel::library_case(name), *dir); rc != cli::kExitOk) return rc;
    }
    return cli::kExitOk;
  }
  if (args.positionals().size() != 1) return usage_error("generate takes one NAME (or --all DIR)");
  const auto output = args.value("output");
  if (!output) return usage_error("generate needs -o DIR");
  const auto c = vessel::library_case(args.positionals()[0]);
  if (!c) return usage_error("unknown case '" + args.positionals()[0] + "' (see `cathbox case list`)");
  return generate(*c, *output);
}

int run_case(std::span<const std::string> argv) {
  return cli::run_group(spec(), argv, [](std::string_view sub, cli::Args& args) {
    if (sub == "list") {
      for (const std::string& name : vessel::library_case_names()) std::printf("%s\n", name.c_str());
      return cli::kExitOk;
    }
    return run_generate(args);
  });
}

const cli::Registrar registrar({spec().name, spec().summary, run_case});

}  // namespace
