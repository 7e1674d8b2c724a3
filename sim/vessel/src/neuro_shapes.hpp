#pragma once
// The shapes the bundled neurovascular network's variants and pathologies take (stenosis, sacs,
// arch types, cervical ICA tortuosity); [n]: the references listed in neuro_case.cpp.
#include <vector>

#include <glm/vec3.hpp>

#include "case_network.hpp"
#include "vessel/case_generator.hpp"

namespace cathbox::vessel::detail {

// Gaussian narrowing: `reduction` of the diameter at arc `center_mm`, half-width `width_mm` ([10]).
[[nodiscard]] RadiusProfile stenosis(double center_mm, double width_mm, double reduction);

// A saccular aneurysm's knots for the morphology's sac shape ([9][14]): a blind segment from
// `base` (the parent's end) along `axis` (details in neuro_shapes.cpp).
[[nodiscard]] std::vector<Knot> sac_knots(const NeuroMorphology& m, const glm::dvec3& base, const glm::dvec3& axis);

// The aortic arch's shape for each arch type [11][12]: the arch is a half ellipse whose top stays
// put; `height_mm` is its vertical semi-axis and the branch origins (degrees along it, 90 = top)
// move down the ascending limb as the type rises.
struct ArchShape {
  double height_mm, bct_deg, lcca_deg, lsa_deg;
};
[[nodiscard]] ArchShape arch_shape(ArchType type);

// Cervical left ICA knots between the bulb and the skull base (Weibel-Fields grades [13]).
[[nodiscard]] std::vector<Knot> cervical_ica(IcaTortuosity t);

}  // namespace cathbox::vessel::detail
