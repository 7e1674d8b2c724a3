#pragma once
// The force law of a node pressed into the wall by w (its plane gap, > 0): K w up to the wall's
// layer, then K (the layer) + s K (w - layer), s = RodSettings::wall_stiffening. The rigid wall's
// numerical penalty has no layer (one stiffness, its hard limit of penetration after the solve);
// a compliant wall's layer is where its collagen fibres are recruited and it stiffens
// (compliant_contact.hpp), so a node pressed harder meets a stiffer wall, not a projection the
// step's energy knows nothing of. The energy is convex and its gradient continuous: the Newton
// solve converges on it. Units: mm, mN.
#include <algorithm>

#include "tool/rod_settings.hpp"

namespace cathbox::tool {

struct WallPenalty {
  double k_mN_per_mm = 0.0;
  double layer_mm = 0.0;  // infinity: one stiffness
  double stiffening = 1.0;

  explicit WallPenalty(const RodSettings& s)
      : k_mN_per_mm(s.contact_stiffness_mN_per_mm), layer_mm(s.wall_layer_mm), stiffening(s.wall_stiffening) {}

  // The normal force at a penetration w (0 for w <= 0).
  [[nodiscard]] double force_mN(double w_mm) const {
    if (!(w_mm > 0.0)) return 0.0;
    if (w_mm <= layer_mm) return k_mN_per_mm * w_mm;
    return k_mN_per_mm * (layer_mm + stiffening * (w_mm - layer_mm));
  }
  // The stiffness at w: the Hessian's along the normal. The active set holds a node on its
  // plane at w <= 0 too (the quadratic continued), so K there.
  [[nodiscard]] double stiffness_mN_per_mm(double w_mm) const {
    return w_mm <= layer_mm ? k_mN_per_mm : k_mN_per_mm * stiffening;
  }
  // The energy whose derivative is the force, the quadratic continued below 0 (the active set's).
  [[nodiscard]] double energy(double w_mm) const {
    if (w_mm <= layer_mm) return 0.5 * k_mN_per_mm * w_mm * w_mm;
    const double over = w_mm - layer_mm;
    return k_mN_per_mm * layer_mm * (0.5 * layer_mm + over) + 0.5 * k_mN_per_mm * stiffening * over * over;
  }
  // The energy's derivative (the force, continued below 0 as the energy is).
  [[nodiscard]] double gradient_mN(double w_mm) const {
    return w_mm <= layer_mm ? k_mN_per_mm * w_mm : force_mN(w_mm);
  }
};

}  // namespace cathbox::tool
