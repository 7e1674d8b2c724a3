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

// Cervical: Riley, Barnes, Evans, Burke, "Ultrasonic measurement of the elastic modulus of the
// common carotid artery. The ARIC Study", Stroke 23(7), 1992: Y = (R / WT) (PP / CAS) in 3,321
// adults, mean 701 kPa (women) and 771 kPa (men) at 45-49 years, 965-983 kPa at 60-64. h / R 0.2:
// an estimate (an intima-media of ~0.6 mm on a 3 mm lumen radius), not one cited measurement.
inline constexpr ArterialWall kCervicalWall{770.0, 0.2, 0.5};
// Intracranial arteries are muscular, with a thin media and no external elastic lamina; their
// incremental modulus at physiological pressure is taken twice the carotid's and their wall a
// tenth-and-a-half of the radius (~0.2 mm on the 1.55 mm M1 radius of Rai et al., J NeuroIntervent
// Surg 5(4), 2013: M1 origin 3.1 +- 0.4 mm). Estimates, not cited measurements (sim/tool/README.md,
// "Compliant wall", limits).
inline constexpr ArterialWall kIntracranialWall{1540.0, 0.15, 0.5};

[[nodiscard]] ArterialWall arterial_wall(Territory territory);

// The tissue's tangential (shear) contact stiffness under a tool's contact patch, per mm of the
// patch's radius (mN/mm^2): a circular patch of radius a held in full stick on an elastic
// half-space of shear modulus G = E / (2 (1 + nu)) moves by T (2 - nu) / (8 G a) under a
// tangential force T (Mindlin, "Compliance of elastic bodies in contact", J Appl Mech 16, 1949;
// Johnson, Contact Mechanics, 1985, §7.2), so k_t = 8 G a / (2 - nu). Beside the flat patch's
// normal stiffness 4 G a / (1 - nu) (Boussinesq) it is 2 (1 - nu) / (2 - nu) of it: 2/3 for
// nearly incompressible tissue. The rod's wall friction sticks with it (RodSettings::
// wall_shear_mN_per_mm2, times the node's radius as the patch's).
[[nodiscard]] constexpr double patch_shear_stiffness_mN_per_mm2(const ArterialWall& wall) {
  const double g = wall.youngs_modulus_kPa / (2.0 * (1.0 + wall.poisson));  // kPa = mN/mm^2
  return 8.0 * g / (2.0 - wall.poisson);
}

class WallShell {
 public:
  WallShell(const ArterialWall& wall, double radius_mm);

  [[nodiscard]] const ArterialWall& wall() const { return wall_; }
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
  ArterialWall wall_;
  double radius_mm_;
  double thickness_mm_;
  double hoop_k_;
  double bending_d_;
  double beta_;
};

}  // namespace cathbox::tool
