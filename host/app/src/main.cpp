// cathbox-trainer: the trainee's application (see host/app/README.md).
#include <cstdio>
#include <exception>
#include <filesystem>
#include <span>

#include "app/trainer_app.hpp"
#include "app/trainer_options.hpp"
#include "base/exit_codes.hpp"

int main(int argc, char** argv) {
  const cathbox::app::OptionsResult parsed = cathbox::app::parse_trainer_options(
      std::span<const char* const>(argv + 1, static_cast<std::size_t>(argc > 0 ? argc - 1 : 0)));
  if (!parsed.options) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", parsed.error.c_str());
    return cathbox::base::kExitBadInput;
  }
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  try {
    cathbox::app::TrainerApp app(*parsed.options, ec ? std::string(".") : exe.parent_path().string());
    return app.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cathbox-trainer: %s\n", e.what());
    return cathbox::base::kExitFailure;
  }
}
