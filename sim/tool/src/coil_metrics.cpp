#include "tool/coil_metrics.hpp"

#include <algorithm>
#include <cmath>

namespace cathbox::tool {
namespace {

double cylinder_volume_mm3(double diameter_mm, double length_mm) { return M_PI / 4.0 * diameter_mm * diameter_mm * length_mm; }

}  // namespace

CoilMetrics::CoilMetrics(const Simulator& sim, const AneurysmSac& sac) : sac_(sac) {
  for (std::size_t t = 0; t < sim.tool_count(); ++t) {
    const ToolSpec& spec = sim.rod(t).spec();
    if (spec.kind == ToolKind::kCoil && spec.detach_mm > 0.0) coils_.push_back(CoilTool{t, sim.outer_of(t)});
  }
}

double CoilMetrics::attached_deployed_mm(const Simulator& sim, std::size_t coil_tool) {
  if (sim.released_mm(coil_tool) > 0.0) return 0.0;
  const double past = sim.tip_depth_mm(coil_tool) - sim.free_start_mm(coil_tool);
  return std::clamp(past, 0.0, sim.rod(coil_tool).spec().detach_mm);
}

int CoilMetrics::herniated(const Rod& rod, std::size_t first, std::size_t end, double leaving_from_tip_mm,
                           double& deepest_mm) const {
  int n = 0;
  const std::span<const glm::dvec3> x = rod.positions();
  for (std::size_t k = first; k < end; ++k) {
    if (rod.node_from_tip_mm(k) > leaving_from_tip_mm) continue;
    const double depth = sac_.depth_mm(x[k]);
    if (depth < -rod.node_radius_mm(k)) {
      ++n;
      deepest_mm = std::max(deepest_mm, -depth);
    }
  }
  return n;
}

void CoilMetrics::detached(double force_mN) {
  if (static_cast<std::size_t>(f_.detachments) < CoilFigures::kMaxDetachments) f_.detach_force_mN[static_cast<std::size_t>(f_.detachments)] = force_mN;
  ++f_.detachments;
  f_.detach_force_peak_mN = std::max(f_.detach_force_peak_mN, std::abs(force_mN));
  if (std::abs(force_mN) > kNeutral_mN) ++f_.detached_under_tension;
}

void CoilMetrics::observe(const Simulator& sim) {
  f_.deployed_mm = 0.0;
  f_.coil_volume_mm3 = 0.0;
  f_.kick_back_now_mm = 0.0;
  int herniated_now = 0;
  double deepest_mm = 0.0;
  for (CoilTool& c : coils_) {
    const Rod& rod = sim.rod(c.tool);
    if (c.load != sim.coils_loaded(c.tool)) {  // the next coil loaded: its kick-back is its own
      c.load = sim.coils_loaded(c.tool);
      c.deploying = false;
    }
    const bool released = sim.released_mm(c.tool) > 0.0;
    if (released && !c.released) detached(c.force_mN);
    c.released = released;
    // The push at the detach command: read until the zone starts to part (Simulator::detach).
    if (!released && !sim.parting(c.tool)) c.force_mN = sim.hand_force_mN(c.tool) - sim.sheath(c.tool).force_mN - sim.valve(c.tool).force_mN;
    const double out = attached_deployed_mm(sim, c.tool);
    if (out > 0.0) {
      f_.deployed_mm += out;
      f_.coil_volume_mm3 += cylinder_volume_mm3(2.0 * rod.radius_at_mm(0.0), out);
      herniated_now += herniated(rod, rod.first_free_node(), rod.node_total(), out - kLeavingZone_mm, deepest_mm);
    }
    if (c.catheter >= sim.tool_count()) continue;
    const double depth = sac_.depth_mm(sim.tip(c.catheter).position_mm);
    const double insertion = sim.insertion_mm(c.catheter);
    if (!c.deploying && (out > 0.0 || sim.released_mm(c.tool) > 0.0)) {
      c.deploying = true;
      c.ref_depth_mm = depth;
      c.ref_insertion_mm = insertion;
    }
    if (c.deploying && sim.released_mm(c.tool) == 0.0) {  // until the coil is released
      const double kick = (c.ref_depth_mm - depth) - (c.ref_insertion_mm - insertion);
      f_.kick_back_now_mm = std::max(f_.kick_back_now_mm, kick);
      f_.kick_forward_mm = std::max(f_.kick_forward_mm, -kick);
    }
  }
  for (std::size_t i = 0; i < sim.detached_count(); ++i) {
    const Rod& coil = sim.released_view(i);  // never waits for a solve the step left running
    f_.deployed_mm += coil.length_mm();
    f_.coil_volume_mm3 += cylinder_volume_mm3(2.0 * coil.radius_at_mm(0.0), coil.length_mm());
    herniated_now += herniated(coil, 0, coil.node_total(), coil.length_mm() + 1.0, deepest_mm);
  }
  f_.packing_density = sac_.volume_mm3 > 0.0 ? f_.coil_volume_mm3 / sac_.volume_mm3 : 0.0;
  // A new episode after a gap without herniated coil (a loop flickering across the plane is one).
  herniation_began_ = false;
  if (herniated_now > 0) {
    herniation_began_ = f_.herniated_nodes == 0 && (f_.herniations == 0 || sim.time_s() - clear_since_s_ >= kHerniationGap_s);
    if (herniation_began_) ++f_.herniations;
  } else if (f_.herniated_nodes > 0) {
    clear_since_s_ = sim.time_s();
  }
  f_.herniated_nodes = herniated_now;
  f_.herniated_peak_nodes = std::max(f_.herniated_peak_nodes, herniated_now);
  f_.herniated_depth_mm = std::max(f_.herniated_depth_mm, deepest_mm);
  f_.kick_back_mm = std::max(f_.kick_back_mm, f_.kick_back_now_mm);
}

}  // namespace cathbox::tool
