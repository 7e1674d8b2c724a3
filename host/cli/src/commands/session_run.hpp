#pragma once
// `cathbox session run`: a headless session recorded to a file (session.cpp has the rest).
#include <span>
#include <string>

namespace cathbox::cli {

int run_run(std::span<const std::string> argv, const char* usage);

}  // namespace cathbox::cli
