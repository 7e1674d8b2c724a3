#include "flow/territory.hpp"

#include <numbers>
#include <string>

namespace cathbox::flow {
namespace {

// ---------------------------------------------------------------------------------------------
// Default flows (resting adult, mL/min). Sources:
//  [1] Hall JE, Hall ME. Guyton and Hall Textbook of Medical Physiology, 14th ed. Elsevier 2021:
//      resting cardiac output ~5 L/min (ch. 20); cerebral blood flow 50-65 mL per 100 g of brain
//      per minute, 750-900 mL/min for the whole brain, ~15 % of the resting cardiac output
//      (ch. 62); mean arterial pressure ~93 mmHg for 120/80 (diastolic + a third of the pulse
//      pressure).
//  [2] Zarrinkoob L, Ambarki K, Wahlin A, Birgander R, Eklund A, Malm J. Blood flow distribution
//      in cerebral arteries. J Cereb Blood Flow Metab 2015;35:648-54. Phase-contrast MRI in 94
//      healthy adults: total cerebral blood flow 717 +- 123 mL/min, carotid/vertebral share
//      72 %/28 % (so ~250 mL/min per internal carotid, ~100 mL/min per vertebral artery); per
//      side MCA 21 %, ACA 12 %, ophthalmic 2 %, PCA 8 %, and 20 % to the basilar artery.
//  [3] Radiology 1997, PubMed 9356614: common carotid volume flow 415 +- 87 mL/min in 174
//      healthy adults (colour M-mode, time-domain processing). The external carotid gets the
//      common carotid's flow less the internal carotid's: 415 - 270 = 145 mL/min, 2.9 % of the
//      cardiac output.
//  [4] Reneman RS, Hoeks APG. Wall shear stress as measured in vivo: consequences for the design
//      of the arterial system. Med Biol Eng Comput 2008;46:499-507: time-averaged wall shear
//      stress ~1.1-1.3 Pa in the common carotid artery of young adults. Murray's law (Murray CD,
//      PNAS 1926;12:207-14) at constant wall shear stress tau gives Q = pi tau r^3 / (4 mu).
//  [5] Pries AR, Neuhaus D, Gaehtgens P. Blood viscosity in tube flow: dependence on diameter
//      and hematocrit. Am J Physiol 1992;263:H1770-8: in tubes wider than ~0.5 mm the relative
//      apparent viscosity at haematocrit 0.45 levels off near 3.2 (x plasma ~1.1-1.2 mPa.s), so
//      blood in the arteries modelled here is taken as Newtonian at 3.5 mPa.s.
// Upper limb (subclavian outlets): 3 % of the cardiac output each side (150 mL/min) — an
// estimate of resting arm and shoulder-girdle flow, not from a single study; it only sets how
// much of the arch's flow leaves through the arms and does not change the flows in the head.
// Everything else leaves through the descending aorta (coronary flow, ~4 % of the output, is
// not modelled and is counted there).
// ---------------------------------------------------------------------------------------------
constexpr double kCarotidShareOfCerebral = 0.72 / 2.0;    // [2] per side
constexpr double kVertebralShareOfCerebral = 0.28 / 2.0;  // [2] per side
constexpr double kMcaOfCarotid = 21.0 / 33.0;             // [2] MCA : ACA = 21 : 12
constexpr double kAcaOfCarotid = 12.0 / 33.0;
// [3] and [1]: (415 - 0.36 * 0.15 * 5000) / 5000
constexpr double kExternalCarotidShareOfOutput = (415.0 - kCarotidShareOfCerebral * 0.15 * 5000.0) / 5000.0;
constexpr double kUpperLimbShareOfOutput = 0.03;          // estimate, see above

std::string normalised(std::string_view name) {
  std::string s(name);
  for (char& c : s) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    if (c == '-' || c == ' ') c = '_';
  }
  return s;
}

bool has(const std::string& s, std::string_view word) { return s.find(word) != std::string::npos; }

double cerebral_ml_min(const FlowSettings& s) { return s.cardiac_output_ml_min * s.cerebral_fraction; }

}  // namespace

Territory territory_of(std::string_view name) {
  const std::string s = normalised(name);
  if (has(s, "communicating")) return Territory::kNone;
  if (has(s, "middle_cerebral")) return Territory::kMiddleCerebral;
  if (has(s, "anterior_cerebral")) return Territory::kAnteriorCerebral;
  if (has(s, "posterior_cerebral") || has(s, "basilar") || has(s, "cerebellar")) return Territory::kPosteriorCerebral;
  if (has(s, "internal_carotid")) return Territory::kInternalCarotid;
  if (has(s, "vertebral")) return Territory::kVertebral;
  if (has(s, "external_carotid")) return Territory::kExternalCarotid;
  if (has(s, "common_carotid")) return Territory::kCommonCarotid;
  if (has(s, "subclavian") || has(s, "axillary") || has(s, "brachial")) return Territory::kUpperLimb;
  if (has(s, "descending_aorta") || has(s, "abdominal_aorta")) return Territory::kDescendingAorta;
  return Territory::kNone;
}

Side side_of(std::string_view name) {
  const std::string s = normalised(name);
  if (s.rfind("left", 0) == 0 || has(s, "_left")) return Side::kLeft;
  if (s.rfind("right", 0) == 0 || has(s, "_right")) return Side::kRight;
  return Side::kNone;
}

bool is_sac_name(std::string_view name) { return has(normalised(name), "aneurysm"); }

std::string_view territory_label(Territory t) {
  switch (t) {
    case Territory::kNone: return "murray";
    case Territory::kMiddleCerebral: return "middle_cerebral";
    case Territory::kAnteriorCerebral: return "anterior_cerebral";
    case Territory::kPosteriorCerebral: return "vertebrobasilar";
    case Territory::kInternalCarotid: return "internal_carotid";
    case Territory::kVertebral: return "vertebral";
    case Territory::kExternalCarotid: return "external_carotid";
    case Territory::kCommonCarotid: return "common_carotid";
    case Territory::kUpperLimb: return "upper_limb";
    case Territory::kDescendingAorta: return "descending_aorta";
  }
  return "murray";
}

double internal_carotid_flow_ml_min(const FlowSettings& s) { return kCarotidShareOfCerebral * cerebral_ml_min(s); }
double vertebral_flow_ml_min(const FlowSettings& s) { return kVertebralShareOfCerebral * cerebral_ml_min(s); }
double common_carotid_flow_ml_min(const FlowSettings& s) {
  return internal_carotid_flow_ml_min(s) + territory_flow_per_side_ml_min(Territory::kExternalCarotid, s);
}

double territory_flow_per_side_ml_min(Territory t, const FlowSettings& s) {
  switch (t) {
    case Territory::kMiddleCerebral: return kMcaOfCarotid * internal_carotid_flow_ml_min(s);
    case Territory::kAnteriorCerebral: return kAcaOfCarotid * internal_carotid_flow_ml_min(s);
    case Territory::kPosteriorCerebral: return vertebral_flow_ml_min(s);
    case Territory::kInternalCarotid: return internal_carotid_flow_ml_min(s);
    case Territory::kVertebral: return vertebral_flow_ml_min(s);
    case Territory::kExternalCarotid: return kExternalCarotidShareOfOutput * s.cardiac_output_ml_min;
    case Territory::kCommonCarotid: return common_carotid_flow_ml_min(s);
    case Territory::kUpperLimb: return kUpperLimbShareOfOutput * s.cardiac_output_ml_min;
    case Territory::kDescendingAorta:
    case Territory::kNone: return 0.0;
  }
  return 0.0;
}

double murray_flow_ml_min(double radius_mm, const FlowSettings& s) {
  const double mu_Pa_s = s.viscosity_mPa_s * 1e-3;
  const double q_mm3_s = std::numbers::pi * s.wall_shear_stress_Pa * radius_mm * radius_mm * radius_mm / (4.0 * mu_Pa_s);
  return q_mm3_s * 0.06;
}

}  // namespace cathbox::flow
