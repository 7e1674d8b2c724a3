#pragma once
// `cathbox session run`: a headless session recorded to a file (session.cpp has the rest).
#include <span>
#include <string>

namespace cathbox::cli {

class Args;
struct GroupSpec;
// `args`: the run subcommand's options, parsed; errors print `group`'s synopsis.
int run_run(Args& args, const GroupSpec& group);

}  // namespace cathbox::cli
