#pragma once
// The secondary (rest) shape of a detachable coil as a rest curvature along it: the magnitude
// (1/mm) and the direction in the material frame (0 = towards m1). The frame is parallel
// transported along the rest shape, so the shape carries no rest twist:
//   helix of loop diameter D and pitch p (turns side by side, p = the coil's od):
//     curvature R / (R^2 + c^2), direction turning at the torsion c / (R^2 + c^2) per mm
//     (R = D/2, c = p / 2 pi);
//   complex ("3D"): arcs of three quarters of a circle of diameter D, each bending 90 degrees
//     further round the tangent than the last, so the loops build a cage instead of a stack.
#include <glm/vec3.hpp>
#include <vector>

#include "tool/tool_spec.hpp"

namespace cathbox::tool {

struct CoilRest {
  double curvature_per_mm = 0.0;
  double direction_rad = 0.0;
};

// Rest curvature of `section` at `from_tip_mm` from the coil's distal tip (zero curvature for a
// section without a shape).
[[nodiscard]] CoilRest coil_rest(const ToolSection& section, double from_tip_mm);

// Loop diameter the rest curvature of a section gives (its loops' diameter seen along the
// helix axis): D for a helix or a complex shape, 0 without a shape.
[[nodiscard]] double coil_loop_diameter_mm(const ToolSection& section);

// The rest shape as a space curve: points every step_mm over `length_mm` from the tip,
// integrated from the rest curvature with a parallel-transported frame (tests, previews).
[[nodiscard]] std::vector<glm::dvec3> coil_rest_curve(const ToolSection& section, double length_mm, double step_mm);

}  // namespace cathbox::tool
