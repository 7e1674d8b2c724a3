#pragma once
// The Orient points' checks and notes on a built network (network_builder.hpp, Orient).
#include <string>

#include <glm/vec3.hpp>

#include "vessel_import/network_builder.hpp"

namespace cathbox::vessel_import {

// "inlet: segment N's start, G mm from the point" (the segment starting nearest the point).
[[nodiscard]] std::string inlet_note(const vessel::VesselModel& model, const glm::dvec3& point_mm, double gap_mm);

// Names the segment nearest `point_mm` kSacName and adds a note to out.oriented; out.error
// ("--sac: ...") when that segment does not end blind (it has children) or starts at an inlet.
void name_sac(NetworkBuild& out, const glm::dvec3& point_mm);

}  // namespace cathbox::vessel_import
