#include "app/fluoro_inputs.hpp"

#include <algorithm>
#include <cmath>

namespace cathbox::app {
namespace {

std::string check_scene(const FluoroScene& s, const std::string& name, std::size_t cell_count) {
  if (cell_count > 0 && !s.cell_iodine_mgI_ml.empty() && s.cell_iodine_mgI_ml.size() != cell_count) {
    return name + ".cell_iodine_mgI_ml: " + std::to_string(s.cell_iodine_mgI_ml.size()) + " cells, the vessel has " +
           std::to_string(cell_count);
  }
  const auto bad = std::find_if(s.cell_iodine_mgI_ml.begin(), s.cell_iodine_mgI_ml.end(),
                                [](float c) { return !std::isfinite(c) || c < 0.0F; });
  if (bad != s.cell_iodine_mgI_ml.end()) {
    return name + ".cell_iodine_mgI_ml[" + std::to_string(bad - s.cell_iodine_mgI_ml.begin()) + "]: must be finite and >= 0";
  }
  for (std::size_t i = 0; i < s.tools.size(); ++i) {
    const FluoroTool& t = s.tools[i];
    const std::string tool = name + ".tools[" + std::to_string(i) + "]";
    if (!(t.radius_mm > 0.0F && t.radius_mm < 10.0F)) return tool + ".radius_mm: must be in (0, 10)";
    for (const glm::vec3& n : t.nodes_mm) {
      if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) return tool + ".nodes_mm: must be finite";
    }
    for (std::size_t m = 0; m < t.markers.size(); ++m) {
      if (!(t.markers[m].from_tip_mm >= 0.0 && t.markers[m].length_mm > 0.0)) {
        return tool + ".markers[" + std::to_string(m) + "]: from_tip_mm must be >= 0 and length_mm > 0";
      }
    }
  }
  return {};
}

}  // namespace

std::string check_fluoro_inputs(const FluoroInputs& in, std::size_t cell_count) {
  if (std::string e = flow::check_pose(in.pose); !e.empty()) return "FluoroInputs.pose: " + e;
  if (!(in.patient_transmission > 0.0 && in.patient_transmission <= 1.0)) {
    return "FluoroInputs.patient_transmission: must be in (0, 1]";
  }
  const std::pair<const FluoroScene*, const char*> scenes[] = {
      {&in.shown, "FluoroInputs.shown"}, {&in.mask, "FluoroInputs.mask"}, {&in.roadmap, "FluoroInputs.roadmap"},
      {&in.roadmap_mask, "FluoroInputs.roadmap_mask"}};
  for (const auto& [scene, name] : scenes) {
    if (std::string e = check_scene(*scene, name, cell_count); !e.empty()) return e;
  }
  return {};
}

}  // namespace cathbox::app
