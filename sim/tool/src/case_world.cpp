#include "tool/case_world.hpp"

#include "tool/tube_network_wall.hpp"

namespace cathbox::tool {

WorldBuild build_world(const Case& c) {
  WorldBuild out;
  if (!c.tubes.empty()) {
    auto wall = std::make_unique<TubeNetworkWall>(c.tubes);
    out.world = std::make_unique<CaseWorld>(std::move(wall), *c.entry);
    return out;
  }
  out.error = c.vessel_path + ":0: vessel files need the vessel and collision modules, which this build lacks";
  return out;
}

}  // namespace cathbox::tool
