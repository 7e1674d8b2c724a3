#pragma once
// A stent retriever: a self-expanding laser-cut nitinol stent at the tip of a push wire
// (ToolSpec::stent), delivered crimped through a microcatheter and unsheathed across a clot,
// where it expands against the wall, integrates the clot and is pulled back into a catheter.
//
// - Expansion: where a node of the stent zone (the distal `length_mm` of the push wire) is out
//   of every catheter around the wire it expands to min(nominal diameter, lumen diameter there),
//   the lumen read from the wall (WallModel::lumen_radius_mm).
// - Radial force, total over the stent's length in a tube of diameter d (nominal D, length L):
//   RF(d) = k L (1 - d / D) for d < D, 0 otherwise: a linear spring of the stent's diametral
//   oversizing, k per mm of stent. Calibrated on the one published band for laser-cut stent
//   retrievers measured in tubes (Janardhan et al., "Optimizing radial force of stent
//   retrievers to minimize vessel wall injury", J NeuroIntervent Surg 2019;11(Suppl 1), abstract
//   P-023: every laser-cut device > 1 N in simulated M2 vessels, 1.5-2.24 mm, and < 1 N in
//   simulated M1 vessels, 2.25-3 mm): the 4 x 20 mm device crosses 1 N between the two bands.
// - Wall friction: the expanded struts press the wall with the radial force; the stent slides
//   on it with kStentWallFriction (its nodes' wall contacts too, Rod::set_distal_friction), so
//   pulling it back costs mu RF on a straight path and more where it is dragged round bends
//   (capstan). mu is calibrated on the straight-model Solitaire removal force of Front Neurol
//   2024 (0.24 N, "Investigation of stent retriever removal forces in an experimental model of
//   acute ischemic stroke", Front Neurol 2024;15:1486738) in a 2.8 mm tube (the bundled M1);
//   the EmboTrap II figure and the tortuous figures of the same study are predictions (tests).
// - Clot integration over the dwell: a fraction 1 - exp(-3 t / embed) of the clot the stent
//   covers is held by its struts (95 % after the embedding time; the dwell before retrieval is
//   3-5 minutes in practice, and longer dwells retrieve more on the first pass: 8 vs 3-5 min,
//   World Neurosurg 2018;110:169-173).
// - Clot capture: a fully integrated stent holds the clot against a pull of kCaptureForce_N(D)
//   (the clot-capturing ability measured as the largest withdrawal force before the stent left
//   a fixed sham clot: 0.39 +- 0.11 N for the small-diameter and 0.56 +- 0.18 N for the
//   large-diameter stents, World Neurosurg 2019;121:e358-e363; taken as 4 and 6 mm devices,
//   linear between and beyond).
#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "tool/tool_spec.hpp"
#include "tool/wall_model.hpp"

namespace cathbox::tool {

inline constexpr double kStentRadialStiffness_N_per_mm = 0.114;  // k: RF per mm of stent at full oversizing
inline constexpr double kStentWallFriction = 0.351;              // struts on the wall
inline constexpr double kStentIntegrationRate = 3.0;             // 1 - exp(-3) = 95 % after embed_s
inline constexpr double kRegaugeMove_mm = 0.25;
inline constexpr double kStentClearance_mm = 0.1;   // the stent's proximal end this far out of the catheter: it fills the lumen
// How far an expanded node's axis may leave the lumen's, of its expanded radius (its contact
// radius is the rest): the cage's lateral stiffness is ~1/1000 of the wall's, so a tension
// round a junction's corner carries the axis to the inner side (stent_retriever.cpp).
inline constexpr double kStentAxisPlay = 0.5;
inline constexpr double kStentFlare_mm = 20.0;       // from the catheter's tip to the full diameter
inline constexpr double kStentPlay = 0.05;          // of the fill radius: a contact's play (the rod's penetration limit)
// The push wire's wall penalty (a tenth of the default, as a coil's): an expanded node pressed
// into a narrowing reads its radial compliance, not a rigid rod's (2e5 mN/mm would read 1 um
// of a 1.3 mm node's 65 um play as 200 mN).
inline constexpr double kStentContactStiffness_mN_per_mm = 2.0e4;                  // a node's lumen is read again past this move

// Total radial force, N, of the stent expanded in a tube of `tube_diameter_mm`.
[[nodiscard]] double stent_radial_force_N(const StentRetrieverSpec& s, double tube_diameter_mm);
// The diameter the stent takes in a lumen of `lumen_diameter_mm`.
[[nodiscard]] double stent_expanded_diameter_mm(const StentRetrieverSpec& s, double lumen_diameter_mm);
// The integrated fraction of the covered clot after `dwell_s` seconds expanded across it.
[[nodiscard]] double stent_integration(const StentRetrieverSpec& s, double dwell_s);
// The pull, N, a fully integrated stent of this nominal diameter holds its clot against.
[[nodiscard]] double stent_capture_force_N(const StentRetrieverSpec& s);

// What the simulator knows of a stent retriever after a step.
struct StentState {
  double unsheathed_mm = 0.0;      // stent length out of every catheter around the push wire
  double radial_force_N = 0.0;     // on the wall, over the unsheathed part
  double min_diameter_mm = 0.0;    // the narrowest expanded diameter (0: nothing unsheathed)
  double max_diameter_mm = 0.0;
  double payload_mN = 0.0;         // the owner's added grip (an integrated clot dragged along)
  std::size_t first_node = 0;      // the unsheathed nodes: first_node .. node_total - 1
};

class Rod;

// The runtime part: per stent node the lumen it was last read in, and the grips it sets.
class StentRetriever {
 public:
  StentRetriever(const StentRetrieverSpec& spec, std::size_t node_total);
  // Reads the lumen where unsheathed nodes moved, sets every stent node's grip on the wall
  // (mu x its share of the radial force, plus its share of the payload; 0 while sheathed).
  void update(Rod& rod, const WallModel& wall);
  void set_payload_mN(double mN) { state_.payload_mN = mN > 0.0 ? mN : 0.0; }
  [[nodiscard]] const StentState& state() const { return state_; }
  [[nodiscard]] const StentRetrieverSpec& spec() const { return spec_; }
  // The expanded diameter of node k as of the last update (0 while sheathed).
  [[nodiscard]] double node_diameter_mm(std::size_t k) const { return k < expanded_mm_.size() ? expanded_mm_[k] : 0.0; }

 private:
  [[nodiscard]] double share_mm(const Rod& rod, std::size_t k) const;

  StentRetrieverSpec spec_;
  std::vector<glm::dvec3> gauged_at_;   // where each node's lumen was read
  std::vector<double> lumen_mm_;        // its diameter there (< 0: not read yet)
  std::vector<double> expanded_mm_;
  std::vector<WallHint> hints_;
  StentState state_;
};

}  // namespace cathbox::tool
