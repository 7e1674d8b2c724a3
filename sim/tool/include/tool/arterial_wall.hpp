#pragma once
// The radial mechanics of an artery's wall: a thin elastic cylindrical shell of radius R,
// thickness h and (incremental, circumferential) Young's modulus E, loaded by the transmural
// pressure and by tools pressing on it. Axisymmetric radial displacement w(x) along the axis obeys
// the long-cylinder equation of Timoshenko & Woinowsky-Krieger, *Theory of Plates and Shells*
// (2nd ed., 1959, §114), a beam on an elastic foundation:
//
//   D w'''' + k w = q(x),   D = E h^3 / (12 (1 - nu^2)),   k = E h / R^2,
//
// q the radial load per wall area (a pressure). Far from ends and loads a uniform pressure P gives
// Laplace's thin-walled distension w = P R^2 / (E h); a load P spread round one circumference
// (a ring load) gives w(0) = P beta / (4 pi R k) and decays as e^(-beta |x|) cos(beta x) with
// beta^4 = 3 (1 - nu^2) / (R^2 h^2) (Hetenyi, *Beams on Elastic Foundation*, 1946). A tool node
// presses on one side of the lumen, not round it: by Betti's reciprocity the ring load's
// stiffness bounds the stiffness under a point load from above (the point load's displacement
// under the load is at least the ring load's of the same total force), so
// `ring_load_stiffness_mN_per_mm()` is the stiffest a wall can be to a tool node.
//
// Units: mm, mN, kPa (1 kPa = 1 mN/mm^2).
#include <cstddef>
#include <vector>

namespace cathbox::tool {

// The wall material and its thickness relative to the lumen radius, per vascular territory.
struct ArterialWall {
  double youngs_modulus_kPa = 770.0;  // incremental, circumferential, at physiological pressure
  double thickness_ratio = 0.2;       // h / R (wall thickness over lumen radius)
  double poisson = 0.5;               // arterial tissue is nearly incompressible
};

enum class Territory {
  kCervical,      // common and cervical internal carotid, vertebral arteries
  kIntracranial,  // intradural ICA, circle of Willis, MCA/ACA/basilar and beyond
};

// Published values (sources in the .cpp and in sim/tool/README.md, "Compliant wall").
[[nodiscard]] ArterialWall arterial_wall(Territory territory);

class WallShell {
 public:
  WallShell(const ArterialWall& wall, double radius_mm);

  [[nodiscard]] double radius_mm() const { return radius_mm_; }
  [[nodiscard]] double thickness_mm() const { return thickness_mm_; }
  // k = E h / R^2: the pressure per radial displacement of a uniformly loaded wall (kPa/mm).
  [[nodiscard]] double hoop_stiffness_kPa_per_mm() const { return hoop_k_; }
  // D = E h^3 / (12 (1 - nu^2)), per unit circumferential length (mN mm).
  [[nodiscard]] double bending_stiffness_mN_mm() const { return bending_d_; }
  // beta = (k / 4D)^(1/4): the axial decay rate of a local load's displacement (1/mm).
  [[nodiscard]] double decay_per_mm() const { return beta_; }
  // The radial stiffness to a load of total force P spread round one circumference of a long
  // tube, P / w(0) = 4 pi R k / beta (mN/mm): an upper bound of a point load's.
  [[nodiscard]] double ring_load_stiffness_mN_per_mm() const;

  // Radial displacement (mm, outward positive) at `stations` stations `spacing_mm` apart along a
  // tube whose two ends are clamped (w = w' = 0, as a vessel tethered by its branches), under
  // the radial load `load_kPa` per station (a pressure; a force F on one station is F / (2 pi R
  // spacing)). Central finite differences of the shell equation; O(stations) banded solve.
  [[nodiscard]] std::vector<double> solve_radial(const std::vector<double>& load_kPa, double spacing_mm) const;

 private:
  double radius_mm_;
  double thickness_mm_;
  double hoop_k_;
  double bending_d_;
  double beta_;
};

}  // namespace cathbox::tool
