#pragma once
// The wall bench_tool's step benchmarks run in: the neuro case's mesh through the collision tree
// or, without the vessel module, a meshed tube of neuro-like size and tortuosity (else an
// analytic tube), with its entry and a name for the benchmark's label.
#include <memory>
#include <string>

#include "tool/simulator.hpp"

namespace cathbox::bench {

struct World {
  std::unique_ptr<tool::WallModel> wall;
  tool::Entry entry;
  std::string name;
};

World make_world();

}  // namespace cathbox::bench
