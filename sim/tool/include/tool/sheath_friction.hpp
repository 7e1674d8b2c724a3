#pragma once
// Friction between a tool and the catheters around it, felt at the hand. In the composite
// model a tool inside a catheter lies on the catheter's centre line; where that line bends the
// inner tool presses on the lumen:
//   - capstan: an axial force T in the inner tool through a turn of angle theta presses with
//     |T| theta (Euler-Eytelwein: pushed or pulled through a bend, F_in / F_out = e^(mu theta));
//   - bending: where the inner tool's bending moment EI k changes (its curvature, or its
//     stiffness where a wire's core ends), the lumen holds the shear, |d(EI k)| / l (beam theory,
//     V = dM/ds), l being the length over which its radial clearance c lets it take up the
//     change, 2 sqrt(2 c / k) (never shorter than the node spacing);
// and Coulomb friction mu N of the lumen liner resists the relative sliding and turning. The
// force is an elastic-plastic anchor (stick, then slip at the limit), like the wall friction,
// lumped over the covered length: sticking, the hand feels the anchor's stiffness; slipping,
// the limit. The reaction (the catheter dragged along by the friction) goes back onto the
// catheters' nodes as loads for the next step. The push of the inner tool's axial force on the
// catheter's bends is applied only where set_bend_reaction says (the simulator: for a coil while
// tuning::kCoilBendReaction, off; for a wire steering its catheter through navigation, lagged
// by a step, it fed back on itself and moved the bundled runs).
// The path ends at the holder's node just past the inner tool's end, the turning of the node
// behind that end taken in proportion to the edge covered (SheathVertex::coverage), and the inner
// tool's stiffness at a vertex is its sections' in series over the vertex's span (a turn there
// bends its softer part; the mean over the proximal edge ratcheted a soft catheter kinked where a
// wire's core ends, a node at a time): the normal forces change by
// the length slid as the inner tool's end and its section boundaries pass the holder's nodes,
// where a path ending at the end point itself stepped at every node (its curvature rising as the
// end neared a node, 1/|end - node|, and its turning lost when the end passed it: a pusher drawn
// back through a microcatheter's tip read a sawtooth of 600 -> 1,100 mN a node).
// The path's turning and curvature are read from its vertices, and a holder's first free node
// (just past the entry, or past the tip of the catheter that carries it) fades in over its first
// edge (SheathVertex::weight): its place goes from the entry line, where it crossed, to its own
// in proportion to the length it is out, and the turning and bending of the vertices round it
// from those of the path without it to those with it. Across so short an edge the direction is
// the node's lateral play, which the bending term read as newtons of normal force; the rule
// before (a vertex nearer than half a spacing to one of another origin left out, then put back)
// stepped the coiling run's wire drawn back by -0.3 N and then -1.4 N in one tick at each of the
// microcatheter's nodes leaving the guide's tip (Simulator::build_sheath_path).
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

namespace cathbox::tool {

// One vertex of the path the inner tool lies on, from its distal end (where its own free part
// begins, or its tip) back to the entry.
struct SheathVertex {
  glm::dvec3 point_mm{0.0};
  std::uint32_t holder = 0;        // tool whose free part the vertex is a node of
  std::uint32_t node = 0;          // that node
  double depth_mm = 0.0;           // depth past the entry along the path
  double inner_ei_Nmm2 = 0.0;      // bending stiffness of the inner tool over the vertex's span (in series)
  double inner_radius_mm = 0.0;
  double clearance_mm = 0.0;       // lumen radius of the holder minus the inner tool's radius
  double mu = 0.0;                 // lumen friction of the holder
  // Share of the vertex's turning the inner tool covers: 1, but for the vertex behind the
  // inner tool's end, whose share grows from 0 to 1 as the end goes from it to the next holder
  // node (the path's first vertex, which the end has not reached).
  double coverage = 1.0;
  // Weight of a holder's first free node fading in over its first edge past its entry (0 as it
  // crosses, 1 a spacing out): the path's turning and bending there are those of the path
  // without it and with it, mixed in this proportion.
  double weight = 1.0;
};

class SheathFriction {
 public:
  struct Result {
    double force_mN = 0.0;           // friction on the inner tool, positive resists insertion
    double torque_mNmm = 0.0;        // positive resists rotation
    double force_limit_fwd_mN = 0.0; // slipping forwards (>= 0) / backwards (<= 0)
    double force_limit_back_mN = 0.0;
    double torque_limit_mNmm = 0.0;
    bool sticking = true;
    bool twist_sticking = true;
    double anchor_mN_per_mm = 0.0;   // the stick spring it was given (the twist's: times r^2)
  };

  // Relative sliding and turning of the inner tool against its catheter in this step, the
  // axial force where the covered part ends (the inner free part's push on its clamp, positive
  // in compression), and the path. `anchor_stiffness` is the stick spring (mN/mm; the twist
  // spring is it times the inner radius squared). Fills the per-vertex reaction on the holders.
  Result update(double slide_mm, double turn_rad, double distal_force_mN, const std::vector<SheathVertex>& path,
                double anchor_stiffness_mN_per_mm);

  // Whether the reaction holds, besides the friction, the axial force's push on the path's turns
  // (t (a - b) at a vertex, a and b the unit directions in and out): then the reactions sum to
  // the inner tool's free-body balance, t_entry a_entry - t_distal b_distal. Off, the holders
  // feel the friction alone (the friction drags them forward and nothing pushes back).
  void set_bend_reaction(bool on) { bend_reaction_ = on; }
  // The reaction on the holders, one per path vertex (the force the inner tool exerts there).
  [[nodiscard]] const std::vector<glm::dvec3>& reaction_mN() const { return reaction_; }
  // Axial force along the path from the distal end (index 0) to the entry, for the last update.
  [[nodiscard]] const std::vector<double>& axial_mN() const { return axial_; }
  void reset();

 private:
  // The steps of update: the path's turning angles and curvatures; the capstan normal forces
  // sliding forwards and backwards (returns the running axial force at the entry for each); the
  // stick spring with slip at the limits; the axial profile and reactions of the friction acting
  // (returns the twist's friction torque limit); the twist spring with slip at that limit.
  void measure_turning(const std::vector<SheathVertex>& path);
  void measure_on(const std::vector<SheathVertex>& path, bool skip_fading, std::size_t first, std::size_t last,
                  std::vector<double>& turning, std::vector<double>& bending);
  std::pair<double, double> capstan_normals(const std::vector<SheathVertex>& path, double distal_force_mN);
  void stick_slide(double k, Result& out);
  double distribute_friction(const std::vector<SheathVertex>& path, double distal_force_mN, const Result& out);
  void stick_twist(double kt, double torque_limit, Result& out);

  double slide_ = 0.0;        // accumulated relative sliding, mm
  double anchor_ = 0.0;       // where the stick spring is relaxed, mm
  double turn_ = 0.0;
  double turn_anchor_ = 0.0;
  bool bend_reaction_ = false;
  std::vector<double> normal_fwd_, normal_back_, axial_, turning_, curvature_, bending_;
  std::vector<double> turning_without_, bending_without_;  // the fading vertices left out
  std::vector<std::size_t> active_;
  std::vector<glm::dvec3> reaction_;
};

}  // namespace cathbox::tool
