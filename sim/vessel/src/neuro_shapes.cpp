#include "neuro_shapes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace cathbox::vessel::detail {
namespace {

// A saccular aneurysm as a blind segment (free end, capped) from `base` along `axis`: the neck
// diameter at the base, widening to the dome diameter, 1.56 domes deep (the bundled MCA sac: 2.4 mm
// neck, 6.4 mm dome, 10 mm deep).
[[nodiscard]] std::vector<Knot> sac_knots(const glm::dvec3& base, const glm::dvec3& axis, double neck_mm, double dome_mm) {
  const double s = dome_mm / 6.4;
  return {{base, 0.5 * neck_mm},           {base + 2.0 * s * axis, 2.0 * s}, {base + 4.5 * s * axis, 3.0 * s},
          {base + 6.5 * s * axis, 3.2 * s}, {base + 8.5 * s * axis, 2.6 * s}, {base + 10.0 * s * axis, 1.4 * s}};
}

// A round sac (SacShape::kRound): the sphere of the dome's diameter cut by the neck plane, that
// plane `offset_mm` out along `axis` from `base` (the parent's end), the segment keeping the neck's
// radius from the base to it (in the mesh that stretch lies in the junction's patch). The sphere's
// centre is sqrt(R^2 - r^2) past the neck plane, so the sac is R + sqrt(R^2 - r^2) deep (R the
// dome's, r the neck's radius); knots 0.5 mm apart on the sphere, the last 0.6 mm short of its top
// (the mesher closes a free end with a cap half a radius beyond it).
[[nodiscard]] std::vector<Knot> round_sac_knots(const glm::dvec3& base, const glm::dvec3& axis, double neck_mm, double dome_mm,
                                                double offset_mm) {
  const double big_r = 0.5 * dome_mm, r = 0.5 * neck_mm;
  const double centre = std::sqrt(big_r * big_r - r * r);  // past the neck plane
  const double depth = big_r + centre;
  const glm::dvec3 neck = base + offset_mm * axis;
  std::vector<Knot> knots{{base, r}, {neck, r}};
  const int steps = static_cast<int>(std::ceil((depth - 0.75) / 0.5));
  for (int k = 1; k <= steps; ++k) {
    const double z = (depth - 0.75) * k / steps;
    knots.push_back({neck + z * axis, std::sqrt(std::max(r * r, big_r * big_r - (z - centre) * (z - centre)))});
  }
  return knots;
}

// Three knots on the arc of radius `bend_radius_mm` that rounds the corner `apex` between the
// limbs from `a` and to `b` (its two tangent points and its middle). A swept tube whose
// centreline bends tighter than its own radius folds its inner wall over itself; a kink's apex
// drawn through the corner itself bent at 0.86 radii (the surface crossed itself there). Rounded
// at two lumen radii, the Catmull-Rom curve through these knots bends no tighter than 1.3 radii.
[[nodiscard]] std::vector<glm::dvec3> rounded_corner(const glm::dvec3& a, const glm::dvec3& apex, const glm::dvec3& b,
                                                     double bend_radius_mm) {
  const glm::dvec3 u = glm::normalize(a - apex);
  const glm::dvec3 v = glm::normalize(b - apex);
  const double half = 0.5 * std::acos(std::clamp(glm::dot(u, v), -1.0, 1.0));  // half the limbs' angle
  const glm::dvec3 centre = apex + glm::normalize(u + v) * (bend_radius_mm / std::sin(half));
  const glm::dvec3 t1 = apex + u * (bend_radius_mm / std::tan(half));
  const glm::dvec3 t2 = apex + v * (bend_radius_mm / std::tan(half));
  const glm::dvec3 middle = centre + glm::normalize(apex - centre) * bend_radius_mm;
  return {t1, middle, t2};
}

// The coil's loop: knots every 45 degrees on a circle of 8 mm (about 3 lumen radii) in the
// coronal plane, descending 9.5 mm front to back over the turn so the strands pass each other.
// Seven knots on a 14 x 17 mm loop bent at 1.14 lumen radii at its top and bottom, and the swept
// wall crossed itself on the inner side there (42 triangle pairs); a circle of knots keeps the
// Catmull-Rom curve's curvature near the circle's.
[[nodiscard]] std::vector<Knot> coiled_ica() {
  constexpr double kLoopRadius = 8.0;
  const double y[] = {15, 14.5, 13, 11.5, 10, 8, 6.5, 5.5, 5.5};
  const double r[] = {2.65, 2.6, 2.6, 2.6, 2.55, 2.5, 2.5, 2.45, 2.45};
  std::vector<Knot> knots{{{28, 14, 138}, 2.8}, {{28, 15, 148}, 2.7}};
  for (int k = 0; k <= 8; ++k) {  // clockwise seen from the front, from the loop's left point
    const double a = k * std::numbers::pi / 4.0;
    knots.push_back({{36.0 - kLoopRadius * std::cos(a), y[k], 156.5 + kLoopRadius * std::sin(a)}, r[k]});
  }
  knots.push_back({{27, 7, 166}, 2.4});
  knots.push_back({{26, 9, 177}, 2.4});
  return knots;
}

}  // namespace

// Gaussian narrowing: `reduction` of the diameter at arc `center_mm`, half-width `width_mm`.
[[nodiscard]] RadiusProfile stenosis(double center_mm, double width_mm, double reduction) {
  return [=](double s, double, double r) {
    const double x = (s - center_mm) / width_mm;
    return r * (1.0 - reduction * std::exp(-x * x));
  };
}

// The sac's knots for the morphology's shape.
[[nodiscard]] std::vector<Knot> sac_knots(const NeuroMorphology& m, const glm::dvec3& base, const glm::dvec3& axis) {
  return m.sac_shape == SacShape::kRound ? round_sac_knots(base, axis, m.neck_mm, m.dome_mm, m.neck_offset_mm)
                                         : sac_knots(base, axis, m.neck_mm, m.dome_mm);
}

// The aortic arch's shape for each arch type [11][12]: the arch is a half ellipse whose top stays
// put; `height_mm` is its vertical semi-axis and the branch origins (degrees along it, 90 = top)
// move down the ascending limb as the type rises. Vertical drop of the brachiocephalic origin
// below the arch top = height * (1 - sin(bct)): type I 5.4 mm (0.8 CCA diameters of 6.4 mm),
// type II 10.5 mm (1.6), type III 13.5 mm (2.1).
[[nodiscard]] ArchShape arch_shape(ArchType type) {
  switch (type) {
    case ArchType::kTypeII: return {36.0, 45.0, 85.0, 130.0};
    case ArchType::kTypeIII: return {46.0, 45.0, 85.0, 130.0};
    default: return {30.0, 55.0, 95.0, 135.0};
  }
}

// Cervical left ICA knots between the bulb and the skull base (Weibel-Fields grades [13]):
// tortuous = S-shaped elongation, coiled = a full loop, kinked = an acute (< 90 degree) angle.
[[nodiscard]] std::vector<Knot> cervical_ica(IcaTortuosity t) {
  switch (t) {
    case IcaTortuosity::kTortuous:
      return {{{28, 14, 138}, 2.8}, {{34, 11, 150}, 2.6}, {{25, 12, 163}, 2.5}, {{30, 10, 175}, 2.4}};
    case IcaTortuosity::kCoiled: return coiled_ica();
    case IcaTortuosity::kKinked: {
      std::vector<Knot> knots{{{28, 14, 140}, 2.8}};
      for (const glm::dvec3& p : rounded_corner({28, 14, 140}, {43, 15, 166}, {29, 10, 172}, 2.0 * 2.5)) knots.push_back({p, 2.5});
      knots.push_back({{29, 10, 172}, 2.4});
      return knots;
    }
    default: return {{{28, 14, 140}, 2.8}, {{27, 12, 160}, 2.4}};
  }
}

}  // namespace cathbox::vessel::detail
