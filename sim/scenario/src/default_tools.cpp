// The tools a case without `tool` lines gets, and those the tests and examples build on.
#include "scenario/case_file.hpp"

namespace cathbox::tool {

ToolSpec default_guidewire() {
  ToolSpec spec;
  spec.name = "guidewire";
  spec.kind = ToolKind::kGuidewire;
  // 0.014" nitinol wire: stiff shaft, tapered core, soft distal 15 mm with a 45 degree tip.
  spec.sections = {ToolSection{1750.0, 0.36, 40.0, 31.0, 0.0}, ToolSection{35.0, 0.36, 3.0, 2.3, 0.0},
                   ToolSection{12.0, 0.36, 0.3, 0.23, 0.0}, ToolSection{3.0, 0.36, 0.3, 0.23, 45.0}};
  spec.friction = 0.08;
  return spec;
}

ToolSpec default_catheter() {
  ToolSpec spec;
  spec.name = "catheter";
  spec.kind = ToolKind::kCatheter;
  // 5F braided catheter with a softer distal 40 mm and a slight angle at the tip.
  spec.sections = {ToolSection{960.0, 1.67, 250.0, 190.0, 0.0}, ToolSection{30.0, 1.67, 40.0, 30.0, 0.0},
                   ToolSection{10.0, 1.67, 20.0, 15.0, 30.0}};
  spec.friction = 0.15;
  spec.inner_diameter_mm = 1.0;
  return spec;
}

ToolSpec default_microcatheter() {
  ToolSpec spec;
  spec.name = "microcatheter";
  spec.kind = ToolKind::kCatheter;
  spec.sections = {ToolSection{1500.0, 0.7, 2.0, 1.6, 0.0}};
  spec.inner_diameter_mm = 0.45;
  spec.friction = 0.1;
  spec.max_spacing_mm = 1.0;
  return spec;
}

ToolSpec default_coil(double length_mm, double loop_diameter_mm) {
  ToolSpec spec;
  spec.name = "coil";
  spec.kind = ToolKind::kCoil;
  ToolSection wind{length_mm, 0.25, 0.02, 0.016, 0.0};
  wind.shape = CoilShape::kHelix;
  wind.loop_diameter_mm = loop_diameter_mm;
  spec.sections = {ToolSection{1800.0, 0.33, 10.0, 8.0, 0.0}, wind};
  spec.detach_mm = length_mm;
  spec.inside = "microcatheter";
  spec.friction = 0.05;
  spec.max_spacing_mm = 1.0;
  spec.tip_spacing_mm = 0.5;
  spec.tip_zone_mm = length_mm + 2.0;
  return spec;
}

}  // namespace cathbox::tool
