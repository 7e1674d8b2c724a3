#pragma once
// Vascular territories of outlets, recognised by segment name, and their default flows. A
// vessel network only has the outlets it has: an outlet named after a territory (M2 branches,
// A2, P2, external carotid, subclavian, descending aorta, ...) drains that territory's share of
// the cardiac output; an outlet without a recognised name drains what Murray's law gives for
// its radius. Sources of every share are in territory.cpp.
#include <string_view>

#include "flow/flow_settings.hpp"

namespace cathbox::flow {

enum class Territory : unsigned char {
  kNone,              // no recognised name: Murray's law
  kMiddleCerebral,    // MCA (M1, M2, ...)
  kAnteriorCerebral,  // ACA (A1, A2, ...)
  kPosteriorCerebral, // PCA, basilar and cerebellar branches: the vertebrobasilar territory
  kInternalCarotid,   // an ICA ending in the model (its whole territory)
  kVertebral,         // a vertebral artery ending in the model
  kExternalCarotid,   // face and scalp
  kCommonCarotid,     // a CCA ending in the model
  kUpperLimb,         // subclavian, axillary, brachial
  kDescendingAorta,   // everything below the arch: the rest of the cardiac output
};

enum class Side : unsigned char { kNone, kLeft, kRight };

// Territory of an outlet named `name` (case-insensitive; '_', '-' and ' ' are equivalent).
[[nodiscard]] Territory territory_of(std::string_view name);
[[nodiscard]] Side side_of(std::string_view name);
// True for names of blind sacs (aneurysms): closed ends unless a case says otherwise.
[[nodiscard]] bool is_sac_name(std::string_view name);
[[nodiscard]] std::string_view territory_label(Territory t);

// Default flow of a territory on one side, mL/min (kDescendingAorta and kNone: 0, they are
// the remainder and Murray's law).
[[nodiscard]] double territory_flow_per_side_ml_min(Territory t, const FlowSettings& settings);
// Default flows of single vessels, each side, mL/min (tests and the README compare the solved
// network with these).
[[nodiscard]] double internal_carotid_flow_ml_min(const FlowSettings& settings);
[[nodiscard]] double vertebral_flow_ml_min(const FlowSettings& settings);
[[nodiscard]] double common_carotid_flow_ml_min(const FlowSettings& settings);
// Murray's law for an outlet of radius r: Q = pi tau r^3 / (4 mu), mL/min.
[[nodiscard]] double murray_flow_ml_min(double radius_mm, const FlowSettings& settings);

}  // namespace cathbox::flow
