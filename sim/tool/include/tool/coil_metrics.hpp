#pragma once
// What the coils did to the aneurysm sac, watched step by step (after each Simulator::step):
//   coil length deployed   coil out of the microcatheter's tip (the attached coil's length past
//                          the furthest catheter tip around it, up to its detachment zone) plus
//                          every released coil
//   packing density        coil volume ÷ sac volume, the clinical figure (typically 20-35 %):
//                          each coil counts as a solid cylinder of its primary wind,
//                          pi/4 d^2 L for the deployed length L and outer diameter d
//   herniated nodes        nodes of deployed coil wholly on the parent artery's side of the neck
//                          plane (deeper than their radius), not counting the last
//                          kLeavingZone_mm of coil leaving the catheter tip
//   herniations            episodes of herniated coil (from none to some, after at least
//                          kHerniationGap_s without any): an error event
//   herniation extent      the most nodes herniated at once and the deepest of them past the
//                          neck plane (mm) so far: an episode may be one node for one tick or
//                          a loop lying in the parent artery for seconds (Abdihalim et al.,
//                          AJNR 2011, grade the protrusion by its extent in the parent lumen)
//   kick-back              how far the microcatheter's tip was pushed back out of the sac along
//                          the neck normal from where it was when its coil began to deploy
//                          until the coil's release, less what its own hand withdrew it (peak, mm)
//   detach force           per detachment, the pusher's push on its coil on the last step
//                          before the release (mN, positive pushing the coil on): its axial
//                          force where it leaves the microcatheter's tip, i.e. its hand force
//                          less the lumen friction of the catheters round it and the
//                          haemostatic valve's grip (both hold the pusher on after the release);
//                          and the largest of them in magnitude. A coil detached in neutral
//                          reads ~0; one detached with the hand still pressing it into the sac
//                          (or pulling it back) reads that load, which the release lets go of
//                          in one step (the hand feels it jump, the microcatheter kicks, the
//                          coil moves). Detachments over kNeutral_mN count as "under tension".
// Nothing allocates after construction.
#include <array>
#include <cstddef>
#include <vector>

#include "tool/aneurysm_sac.hpp"
#include "tool/simulator.hpp"

namespace cathbox::tool {

struct CoilFigures {
  double deployed_mm = 0.0;
  double coil_volume_mm3 = 0.0;
  double packing_density = 0.0;   // fraction (0.25 = 25 %)
  int herniated_nodes = 0;        // this step
  int herniations = 0;            // episodes so far
  int herniated_peak_nodes = 0;   // the most nodes herniated at once so far
  double herniated_depth_mm = 0.0;  // the deepest herniated node past the neck plane so far
  double kick_back_mm = 0.0;      // peak so far
  double kick_back_now_mm = 0.0;  // this step
  // The microcatheter tip's climb into the sac (its depth past the neck beyond what its hub's
  // insertion gives) while a coil goes out: kick-back's other sign, peak so far.
  double kick_forward_mm = 0.0;
  // Detachments so far, and the pusher's push on its coil at each (the first kMaxDetachments kept).
  static constexpr std::size_t kMaxDetachments = 16;
  int detachments = 0;
  std::array<double, kMaxDetachments> detach_force_mN{};
  double detach_force_peak_mN = 0.0;  // the largest |force| at any detachment so far
  int detached_under_tension = 0;     // detachments with |force| > CoilMetrics::kNeutral_mN
};

class CoilMetrics {
 public:
  static constexpr double kLeavingZone_mm = 1.0;
  static constexpr double kHerniationGap_s = 0.05;
  // The largest push a detachment counts as "in neutral" at: between a coil released free in a
  // sphere (~2 mN, coil_in_sphere_test) and the bundled frame's push held against the dome at its
  // markers (203 mN; docs/sim-tool/convergence.md, "Detaching in neutral"); not a clinical figure.
  static constexpr double kNeutral_mN = 30.0;

  CoilMetrics(const Simulator& sim, const AneurysmSac& sac);

  // True when the simulator carries a coil tool (else every figure stays 0).
  [[nodiscard]] bool has_coils() const { return !coils_.empty(); }
  void observe(const Simulator& sim);
  [[nodiscard]] const CoilFigures& figures() const { return f_; }
  // Events of the last observe().
  [[nodiscard]] bool herniation_began() const { return herniation_began_; }
  [[nodiscard]] const AneurysmSac& sac() const { return sac_; }

  // Deployed length of one coil tool's attached coil (0 once released).
  [[nodiscard]] static double attached_deployed_mm(const Simulator& sim, std::size_t coil_tool);

 private:
  struct CoilTool {
    std::size_t tool = 0;
    std::size_t catheter = 0;   // the microcatheter it leaves (tool_count() if none)
    bool deploying = false;     // its coil has begun to leave the catheter
    double ref_depth_mm = 0.0;  // the catheter tip's depth in the sac then ...
    double ref_insertion_mm = 0.0;  // ... and the catheter's insertion
    std::size_t load = 0;       // the coil on the tool (Simulator::coils_loaded): a new one deploys afresh
    bool released = false;      // its coil is released (seen at the last observe)
    double force_mN = 0.0;      // its axial force (above) at the last observe while its coil was attached
  };
  // A release seen on this observe: the pusher's force before it.
  void detached(double force_mN);
  // Herniated nodes of rod[first, end) within leaving_from_tip_mm of its tip, the deepest past
  // the neck plane raising `deepest_mm`.
  [[nodiscard]] int herniated(const Rod& rod, std::size_t first, std::size_t end, double leaving_from_tip_mm,
                              double& deepest_mm) const;

  AneurysmSac sac_;
  std::vector<CoilTool> coils_;
  CoilFigures f_;
  bool herniation_began_ = false;
  double clear_since_s_ = -1.0;  // simulated time since when no node has herniated (-1: never any)
};

}  // namespace cathbox::tool
