#pragma once
// `cathbox vessel mesh` and `cathbox vessel import` (vessel.cpp has the group and the rest).
#include <optional>
#include <string>

#include "vessel/vessel_model.hpp"

namespace cathbox::cli {

class Args;
struct GroupSpec;
// `args`: the subcommand's options, parsed; errors print `group`'s synopsis.
int run_mesh(Args& args, const GroupSpec& group);
int run_import(Args& args, const GroupSpec& group);

// Reads and validates; on bad input prints one line: the first problem (and how many more).
std::optional<vessel::VesselModel> read_model(const std::string& path);

}  // namespace cathbox::cli
