#pragma once
// The arch-to-Willis network of the bundled neurovascular cases (CaseGenerator::neuro and its
// variants), drawn with case_network.hpp from the dimensions cited in neuro_case.cpp.
#include "case_network.hpp"
#include "vessel/case_generator.hpp"

namespace cathbox::vessel::detail {

// The network with the given morphology; `stenosed`: a 70 % stenosis at the left ICA origin.
[[nodiscard]] VesselModel build_neuro(const NeuroMorphology& m, bool stenosed);

}  // namespace cathbox::vessel::detail
