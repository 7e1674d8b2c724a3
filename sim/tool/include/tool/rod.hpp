#pragma once
// One tool (guidewire or catheter) as a discrete elastic rod, solved quasi-statically at every
// step. Model: Bergou, Wardetzky, Robinson, Audoly, Grinspun, "Discrete Elastic Rods",
// SIGGRAPH 2008 (curvature binormal, material frames, reference twist) with the quasi-static
// twist and time-parallel reference frames of Bergou et al., "Discrete Viscous Threads",
// SIGGRAPH 2010. Centreline positions are found by Gauss-Newton on the elastic + contact +
// friction + drag energy with a banded Cholesky solve (O(n) per iteration); twist angles by
// a tridiagonal Newton solve. Wall contacts are stiff penalties on planes from the wall probe,
// Coulomb friction a stick spring with a slip limit (elastic-plastic anchor model).
//
// Nodes are material points fixed along the tool (finer towards the tip). The tool enters the
// body at the entry point along the entry direction: nodes not yet past the entry sit on the
// entry line, the last two of them clamp the rod (position, direction and rotation); further
// proximal ones are not simulated, so nodes join and leave the simulation at the entry.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "tool/force_law.hpp"
#include "tool/index_range.hpp"
#include "tool/rod_contacts.hpp"
#include "tool/rod_settings.hpp"
#include "tool/tool_spec.hpp"
#include "tool/wall_model.hpp"

namespace cathbox::tool {

class BandedCholesky;

struct TipPose {
  glm::dvec3 position_mm{0.0};
  glm::dvec3 direction{0.0, 0.0, 1.0};  // unit tangent, distal
  glm::dvec3 normal{1.0, 0.0, 0.0};     // material director m1 (the pre-curve bends towards it)
};

class Rod {
 public:
  Rod(const ToolSpec& spec, const RodSettings& settings = {});
  ~Rod();
  Rod(Rod&&) noexcept;
  Rod& operator=(Rod&&) noexcept;
  Rod(const Rod&) = delete;
  Rod& operator=(const Rod&) = delete;

  // A rod that stands for `rod` in a rod-contact field and a coil sleep read by one thread while
  // another solves `rod` (Simulator: the released coils solved beside the attached tools): its
  // nodes, radii, arc lengths, window and settings, as of the last mirror; it is never stepped.
  [[nodiscard]] static Rod contact_view_of(const Rod& rod);
  void mirror_contact_view(const Rod& rod);  // no allocation once sized to it
  // The contact view and what a reader of a solved rod's results takes of it besides (its
  // tangents and directors, its wall contacts, whether its last solve converged): a released
  // coil as the Simulator publishes it while its next solve runs (Simulator::released_view).
  void mirror_published_view(const Rod& rod);

  // Entry point (introducer) and inward direction; resets the tool to fully withdrawn.
  void set_entry(const glm::dvec3& point_mm, const glm::dvec3& direction);
  // Proximal boundary from the box; insertion is clamped to [0, max_insertion_mm()].
  void set_boundary(double insertion_mm, double rotation_rad);
  // Coaxial use: the entry moves with the outer tool's tip without resetting the tool;
  // `reference` is the director that rotation 0 points to (normal to direction).
  void move_entry(const glm::dvec3& point_mm, const glm::dvec3& direction, const glm::dvec3& reference);
  // How far the material advances in the next step, when it differs from the insertion change
  // (an inner tool whose entry rides on the outer tool's tip). NaN: the insertion change.
  void set_material_advance(double advance_mm) { material_advance_mm_ = advance_mm; }
  // A tool running ahead of this one (the inner wire beyond a catheter's tip): the predictor
  // continues this tool's path along it. leader_insertion_mm is the leader's depth of its tip
  // past this tool's entry. nullptr: straight ahead.
  void set_leader(const Rod* leader, double leader_insertion_mm) {
    leader_ = leader;
    leader_insertion_mm_ = leader_insertion_mm;
  }
  // One quasi-static step of dt seconds against the wall (and other rods, when given); solved
  // again in sub-increments when it ends unconverged (RodSettings::substeps_max).
  void step(double dt_s, const WallModel& wall, const RodObstacles* obstacles = nullptr);

  // Detaches the distal `length_mm` of the tool (a coil at its detachment zone, which must be
  // a node: ToolSpec::detach_mm) and returns it as a free rod: no clamp, held only by drag,
  // the wall and other rods. This rod keeps the proximal part (its tip is the detachment
  // point; insertion and length shrink by length_mm).
  [[nodiscard]] Rod split_distal(double length_mm);
  // The detachment zone parting before split_distal: the bending and twisting stiffness of the
  // vertex `length_mm` from the tip (the joint of coil and pusher) at `share` of their built values
  // (1 restores them). False if that station is not a vertex of the rod.
  bool soften_joint(double length_mm, double share);
  // True for a free rod (a detached coil).
  [[nodiscard]] bool free() const { return free_; }
  // The wall changed (a new collision tree): every node is probed afresh in the next step.
  void forget_wall();
  // The next step starts from where the rod is, not from its last motion (a released coil woken
  // from sleep starts as a coil at rest).
  void forget_motion() { warm_ok_ = false; }

  // Test and coupling hooks.
  void set_node_load(std::size_t node, const glm::dvec3& force_mN);  // constant external force
  void clear_node_loads();
  // Loads from coupled tools (the tool inside this one), reset by the simulator every step.
  void add_coupling_load(std::size_t node, const glm::dvec3& force_mN);
  void clear_coupling_loads();
  // Holds node k where it is now with an elastic-plastic anchor that slips beyond limit_mN
  // (an inflated balloon gripping the wall); 0 releases it.
  void set_grip(std::size_t node, double limit_mN);
  // Added EI (a coaxial inner tool) on the nodes first .. first + size - 1; 0 on the others.
  void set_extra_bending(std::size_t first, std::span<const double> ei_Nmm2);
  void set_friction(double mu) { spec_.friction = mu > 0.0 ? mu : 0.0; }
  // Wall friction mu on the nodes within `length_mm` of the tip (a stent retriever's struts),
  // the tool's own elsewhere.
  void set_distal_friction(double length_mm, double mu);
  // Node k's radius against the wall (an expanded stent filling the lumen); its section's
  // radius when `radius_mm` is not above it.
  void set_contact_radius(std::size_t k, double radius_mm);
  [[nodiscard]] double friction_at(std::size_t k) const { return k >= distal_first_ ? distal_mu_ : spec_.friction; }
  // Wall friction's stick spring at node k (mN/mm): the tissue's shear stiffness under a patch
  // of the node's radius (RodSettings::wall_shear_mN_per_mm2).
  // 0 shear (a coil): stick_stiffness_ratio of the contact stiffness, as the other stick springs.
  [[nodiscard]] double wall_stick_mN_per_mm(std::size_t k) const {
    return settings_.wall_shear_mN_per_mm2 > 0.0 ? settings_.wall_shear_mN_per_mm2 * radius_[k]
                                                 : settings_.stick_stiffness_mN_per_mm();
  }
  RodSettings& settings() { return settings_; }
  [[nodiscard]] const RodSettings& settings() const { return settings_; }
  // Whether the hand draws the tool back this step: it then bends from the entry point as
  // RodSettings::clamp_hinge_at_entry does, switched at node crossings only; before the first,
  // its hinge walks from the clamp node to the entry point with the draw-back (update_window).
  void hinge_while_drawn_back(bool drawn_back) { drawn_back_ = drawn_back; }
  // How far ahead of the clamp node its edge bends from (the clamp's hinge, toward the entry
  // point): 0 while the clamp edge bends at the clamp node.
  [[nodiscard]] double clamp_shift_mm() const { return clamp_shift_mm_; }

  // Properties of the tool at a distance from its tip.
  [[nodiscard]] double radius_at_mm(double from_tip_mm) const;
  [[nodiscard]] double bending_at_Nmm2(double from_tip_mm) const;
  [[nodiscard]] double inner_radius_at_mm(double from_tip_mm) const;
  // The same at a station found by walking from `station` (updated; start with kNoStation), for
  // callers that look up monotonic sequences of distances: the same answers without a search each.
  static constexpr std::size_t kNoStation = std::numeric_limits<std::size_t>::max();
  [[nodiscard]] double radius_at_mm(double from_tip_mm, std::size_t& station) const;
  [[nodiscard]] double bending_at_Nmm2(double from_tip_mm, std::size_t& station) const;
  [[nodiscard]] double inner_radius_at_mm(double from_tip_mm, std::size_t& station) const;
  // The integral of the sections' EI (N mm^3) over the stations [near_mm, far_mm] from the tip,
  // the part off the tool (past its tip or its proximal end) counting nothing. Divided by a
  // length it is the mean stiffness over it, continuous as the tool slides: a section boundary
  // or the tip passing a point changes it by the slid length, not in one step.
  [[nodiscard]] double bending_integral_Nmm3(double near_mm, double far_mm) const;
  // The bending stiffness over [from_mm, to_mm] (from the proximal end), its sections'
  // compliances in series; fallback_Nmm2 for an empty span or an unbendable section in it.
  [[nodiscard]] double vertex_bending_Nmm2(double from_mm, double to_mm, double fallback_Nmm2) const;

  [[nodiscard]] const ToolSpec& spec() const { return spec_; }
  [[nodiscard]] double insertion_mm() const { return insertion_mm_; }
  [[nodiscard]] double rotation_rad() const { return rotation_rad_; }
  [[nodiscard]] double max_insertion_mm() const;
  [[nodiscard]] double length_mm() const { return length_mm_; }

  // The simulated window: nodes [first_node(), node_total()), tip last. Nodes with depth <= 0
  // are outside the body on the entry line.
  [[nodiscard]] std::size_t node_total() const { return x_.size(); }
  [[nodiscard]] std::size_t first_node() const { return first_; }
  [[nodiscard]] std::size_t first_free_node() const { return first_free_; }
  // First edge the solve moves (the one leaving the clamp; 0 for a free rod).
  [[nodiscard]] std::size_t first_edge() const { return free_ ? 0 : first_free_ - 1; }
  [[nodiscard]] std::span<const glm::dvec3> positions() const { return x_; }
  [[nodiscard]] std::span<const glm::dvec3> tangents() const { return t_; }    // per edge k: k -> k+1
  [[nodiscard]] std::span<const glm::dvec3> directors() const { return m1_; }  // per edge, m1
  [[nodiscard]] double node_radius_mm(std::size_t k) const { return radius_[k]; }
  [[nodiscard]] double node_depth_mm(std::size_t k) const { return insertion_mm_ - from_tip_[k]; }
  [[nodiscard]] double node_from_tip_mm(std::size_t k) const { return from_tip_[k]; }
  [[nodiscard]] TipPose tip() const;
  [[nodiscard]] std::span<const RodContact> contacts() const { return contacts_; }
  // Contacts with other rods (and itself) held in the last step, with their forces.
  [[nodiscard]] std::span<const EdgeContact> edge_contacts() const { return edge_contacts_; }
  // Rest curvature at node k (1/mm, magnitude) of the pre-curve or coil shape.
  [[nodiscard]] double rest_curvature_per_mm(std::size_t k) const;
  // Force the rod exerts on its clamp (the entry), lateral components included.
  [[nodiscard]] glm::dvec3 clamp_force_mN() const;
  // The sum of the magnitudes of the external forces on the free nodes after the last step: the
  // walls' normal force and friction, other rods' and its own contacts, the loads, a balloon's
  // grip (its slip limit at most), the drag the solve balanced. The clamp holds the free part
  // against their vector sum, in equilibrium, so no more than this: a clamp force above it is
  // balanced by nothing on the free part (the clamp force is linearised on to the moves after the
  // solve, penetration limits and rod-rod projections, which report no force; sim/tool README,
  // "Coaxial tools").
  [[nodiscard]] double free_part_load_mN() const { return free_part_load_mN_; }

  // What the tool exerts on the hand: positive resists insertion / rotation. A solve that
  // converged on a step it took only in part (the line search cut it) or beyond it (extended)
  // gives the clamp force at the linearised equilibrium its convergence test read, the step taken
  // whole, as a rod among other rods always does (linearise_clamp).
  [[nodiscard]] double hand_force_mN() const { return hand_force_mN_; }
  // The axial force on the clamp linearised on to the moves the step took (hand_force_mN() but
  // on those ticks): what a carrier's capstan reads from the free part (Simulator::update_sheath).
  [[nodiscard]] double clamp_read_mN() const { return clamp_read_mN_; }
  [[nodiscard]] double hand_torque_mNmm() const { return hand_torque_mNmm_; }
  [[nodiscard]] const ForceLaw& force_law() const { return law_; }
  // Solver diagnostics of the last step: iterations used.
  [[nodiscard]] int last_iterations() const { return last_iterations_; }
  // Solver work since the rod was made (bench/tool's deterministic counters): factorisations
  // (whole or from a row), block rows factored, solves of the factor, line-search tries.
  struct SolverWork {
    std::uint64_t factors = 0, rows_factored = 0, solves = 0, line_tries = 0;
  };
  [[nodiscard]] SolverWork solver_work() const;
  // Sub-increments the last tick was solved in: 1, or 2, 4 ... after an unconverged solve.
  [[nodiscard]] int last_substeps() const { return last_substeps_; }
  // The last step's Newton iterations met the convergence test: its contact forces (the
  // penalty of each node's penetration) are close to an equilibrium's, not exactly one's: after
  // the test the step still moves nodes, limit_penetration() pushing any node past the
  // penetration limit back to it and, for a rod among other rods (coils, the catheter they
  // leave), the rod-rod projection rounds (finish_edge_contacts()). A step that ran out of
  // iterations reads whatever penetration it ended with (2·10^5 mN/mm: 1 um reads 200 mN, up
  // to the cap of 5 % of the radius). False too while no node is free (nothing was solved).
  [[nodiscard]] bool converged() const { return warm_ok_; }
  // Point on the tool's centreline at a depth past the entry (clamped to the tool), its
  // tangent and the index of the node just proximal to it.
  [[nodiscard]] glm::dvec3 point_at_depth(double depth_mm, glm::dvec3* tangent, std::size_t* node) const;
  // Present position of the material station `from_tip_mm` from the tip (on the entry line
  // when it is outside the simulated window).
  [[nodiscard]] glm::dvec3 point_at_from_tip(double from_tip_mm) const;
  [[nodiscard]] const glm::dvec3& entry_point() const { return entry_; }
  [[nodiscard]] glm::dvec3 reference_director(std::size_t edge) const { return d1_[edge]; }

 private:
  // The drag the solver applies at node k: the physical one, never below the numerical floor.
  [[nodiscard]] double solver_drag(std::size_t k) const {
    return std::max(drag_per_mm_[k], settings_.min_drag_mN_s_per_mm2) * voronoi_[k];
  }
  struct NodeContact;  // a node's wall contact (src/rod_node_contact.hpp)
  struct Newton;       // the Newton solve's state within a step (src/rod_newton.hpp)
  struct StepStart;    // the state a step starts from (src/rod_step_start.hpp)
  Rod();  // an empty rod, filled by split_distal

  // Construction (rod.cpp, rod_material.cpp).
  void size_state();
  [[nodiscard]] const ToolSection& section_at(std::size_t k) const;
  void size_scratch();
  // Radius, stiffnesses, rest shape and drag of node k from the section holding it.
  void set_node_material(std::size_t k);
  void set_rest_shape(std::size_t k, double curvature_per_mm, double direction_rad);
  // The step's stiffness and drag coefficients (axial_k_, bend_w_, drag_k_), once per step.
  void update_weights(double dt_s);

  // The simulated window and the predictor (rod.cpp, rod_predictor.cpp).
  void place_outside(std::size_t k);
  void update_window();
  void advect(double delta_mm);
  bool seed_buckling();  // seeds a compressed rod lying within one plane through its entry; whether it did

  // A tick solved again in sub-increments (rod_substep.cpp).
  void step_once(double dt_s, const WallModel& wall, const RodObstacles* obstacles);
  void save_step_start();
  void restore_step_start(int parts);
  // The phases of step_once() (rod_step.cpp, rod_newton.cpp).
  void begin_step();               // the predictor moves the tool by the insertion change
  void start_solve(Newton& s, double dt_s);  // warm start, weights, contacts, active set
  void solve_positions(Newton& s); // Gauss-Newton iterations on the node positions
  // Penetration limits, rod-rod projections, clamp force; true: the clamp took in the moves
  // after the solve (linearise_clamp).
  bool finish_solve(const Newton& s);
  // One Newton iteration's phases, in order.
  void build_system(Newton& s);    // assemble (or amend) and factor
  void add_joined_wall_terms(Newton& s);
  [[nodiscard]] bool newton_direction(Newton& s);  // false: not finite
  bool join_wall(Newton& s, int it);  // nodes the step would carry into the wall join: true
  void predict_edge_contacts(Newton& s);  // the step solved again with the rod-rod planes it crosses
  std::size_t take_crossed_planes();  // one pass of it: first node whose blocks changed
  void solve_with_taken_planes(const Newton& s, std::size_t from);
  [[nodiscard]] double largest_update() const;  // the largest node update in delta_
  void damp_reversal(Newton& s);
  void line_search(Newton& s);
  void place(double scale);  // free nodes at x_pred_ + scale delta_
  void extend(Newton& s, double slope, double e0, double e1);  // past a full step the Hessian held too stiff
  void hold_gaps(const Newton& s);
  void update_active_set(Newton& s);
  void follow_moves(Newton& s);    // re-probe the wall, take other rods' planes again
  // After the iterations.
  void settle_held_nodes();
  void project_contacts(const RodObstacles* obstacles);
  bool linearise_clamp(const Newton& s);  // true: linearised on to the moves after the solve

  // (Helpers declared inline are defined, always inlined, in the one file that calls them, or in
  // rod_newton.hpp when the energy and the twist both do: the hot loops of the assembly and the
  // twist solve keep the code they had as lambdas.)

  // Energy, gradient and Hessian of the step (rod_energy.cpp).
  // Bending residual at vertex i (first_ + 1 .. n - 2) from the unit tangents either side.
  [[nodiscard]] inline glm::dvec3 bend_residual(std::size_t i, const glm::dvec3& ta, const glm::dvec3& tb) const;
  // The scale of vertex i's rest turn: the clamp vertex's and the first free node's with the
  // clamp's hinge at the entry point (hinge_turn_scale_), 1 elsewhere.
  [[nodiscard]] double turn_scale(std::size_t i) const {
    const std::size_t h = i - (first_ + 1);
    return h < 2 ? hinge_turn_scale_[h] : 1.0;
  }
  // The clamp edge's bending chord (RodSettings::clamp_hinge_at_entry): from the entry point, or
  // as near it as kClampEdgeFloor lets, to the first free node.
  [[nodiscard]] glm::dvec3 clamp_chord() const { return x_[first_ + 2] - (x_[first_ + 1] + dir_ * clamp_shift_mm_); }
  inline void add_grad(std::size_t k, const glm::dvec3& g);  // grad_ at node k (rod_newton.hpp)
  void assemble(bool hessian);
  static void estimate_curvature(NodeContact& c, const WallContact& wc);
  double geo_floor_ = 0.0;
  // Drag, loads, grip, wall penalty and friction at free node k: its diagonal block.
  [[nodiscard]] inline glm::dmat3 node_terms(std::size_t k);
  inline void add_edge_terms(std::size_t k, double w_sum, bool hinge, bool hessian, glm::dvec3& u, double& inv, double& ks,
                             glm::dmat3& pc);
  inline void add_grip_terms(std::size_t k, glm::dmat3& h);
  inline void add_wall_terms(std::size_t k, glm::dmat3& h);
  void add_edge_contact_terms(bool hessian);
  [[nodiscard]] double energy() const;

  // Wall contacts (rod_wall_contact.cpp, gaps inline in rod_node_contact.hpp).
  [[nodiscard]] glm::dvec3 gap_normal(std::size_t k) const;
  [[nodiscard]] inline double plane_gap(std::size_t k) const;   // penetration of node k into its plane
  [[nodiscard]] inline double second_gap(std::size_t k) const;  // ... into its second plane
  // Re-probes the wall; true when the plane of a node in the active set was replaced.
  // keep_creases (within a solve): a node keeps a crease's second plane the re-probe drops.
  bool refresh_contacts(const WallModel& wall, bool only_moved, bool keep_creases = false);
  void limit_penetration();
  void finish_contacts();
  void add_second_contact(std::size_t k);
  // The wall against edge k -> k + 1 (rod_edge_wall.cpp, gap inline in rod_node_contact.hpp):
  // a plane where the wall bulges between the nodes (a carina's apex, a bend's inner side).
  [[nodiscard]] inline double edge_wall_gap(std::size_t k) const;
  bool refresh_edge_walls(const WallModel& wall, bool only_moved);
  bool refresh_edge_wall(const WallModel& wall, std::size_t k, bool only_moved);
  [[nodiscard]] bool edge_may_bulge(std::size_t k) const;
  [[nodiscard]] double node_wall_distance(std::size_t j) const;
  void add_edge_wall_term(std::size_t k, bool hessian);
  void add_edge_wall_terms(bool hessian);
  [[nodiscard]] double edge_wall_energy() const;
  bool join_edge_walls();
  void update_edge_wall_set(Newton& s);
  void limit_edge_walls();
  void add_edge_wall_contacts();

  // Contacts with other rods (rod_edge_contact.cpp).
  [[nodiscard]] inline double edge_gap(const EdgeContact& c) const;
  void gather_obstacles(const RodObstacles& obstacles);
  [[nodiscard]] bool moved_since_gather(double limit_mm) const;  // a free node moved more since the gather
  bool finish_edge_contacts();  // true when it had to push a node out
  void slip_grips();

  // Frames and twist (rod_twist.cpp).
  void update_frames();
  inline void set_material_frame(std::size_t e);
  void solve_twist(double dt_s);
  [[nodiscard]] bool assemble_twist(double dt_s, std::size_t ef, std::size_t m);  // false: nonlinear
  // What an assembly of the twist system carries from vertex to vertex: the last edge whose
  // material frame it set, and the last edge's unit tangent (each edge's once, not at both of
  // its vertices: neither the angles nor the nodes change within it).
  struct TwistSweep {
    std::size_t framed = std::numeric_limits<std::size_t>::max();  // none yet
    std::size_t tangent_edge = std::numeric_limits<std::size_t>::max();
    glm::dvec3 tangent{0.0};
  };
  void add_twist_curvature(std::size_t i, std::size_t ef, TwistSweep& sweep);
  void add_twist_curvature_kb(std::size_t i, std::size_t ef, TwistSweep& sweep);
  void add_twist_holonomy_loads();
  void add_twist_stiffness(bool hessian);
  [[nodiscard]] double twist_stiffness_energy() const;
  void add_twist_friction(std::size_t ef);
  [[nodiscard]] inline std::uint8_t twist_regime(std::size_t k, double& ktr, double& limit, double& d) const;
  [[nodiscard]] bool update_twist(std::size_t ef, std::size_t m, bool linear);  // false: nonlinear
  [[nodiscard]] bool twist_regimes_same() const;
  void twist_substitute(std::size_t m);
  void hand_twist(double dt_s, std::size_t ef, std::size_t m);

  // Detaching (rod_detach.cpp).
  [[nodiscard]] std::size_t station_vertex(double length_mm) const;  // node_total() if none
  void copy_distal(Rod& coil, std::size_t k0, double length_mm) const;
  void keep_proximal(std::size_t k0, double length_mm);

  // The force law for the box (rod_force_law.cpp).
  // `clamp_after_moves`: finish_solve's word (the hand force is then bounded by the free part's loads).
  void compute_force_law(double dt_s, bool clamp_after_moves);
  [[nodiscard]] double sum_free_part_loads(double dt_s) const;  // free_part_load_mN_ (rod_force_law.cpp)

  ToolSpec spec_;
  RodSettings settings_;
  double length_mm_ = 0.0;
  glm::dvec3 entry_{0.0};
  glm::dvec3 dir_{0.0, 0.0, 1.0};
  glm::dvec3 entry_d1_{1.0, 0.0, 0.0};
  double insertion_mm_ = 0.0;
  double rotation_rad_ = 0.0;
  double stepped_insertion_mm_ = 0.0;  // insertion at the end of the last step
  double stepped_rotation_rad_ = 0.0;  // rotation at the end of the last step
  bool compressed_ = false;            // the last step ended with an edge compressed past buckling_strain
  bool jammed_ = false;                // ... past warm_start_strain
  double material_advance_mm_ = std::numeric_limits<double>::quiet_NaN();
  const Rod* leader_ = nullptr;
  double leader_insertion_mm_ = 0.0;
  std::size_t first_ = 0;       // first simulated node
  std::size_t first_free_ = 0;  // first node past the entry
  bool free_ = false;           // detached: every node free, no clamp
  // RodSettings::clamp_hinge_at_entry: how far ahead of the clamp node (first_ + 1), up the
  // entry line, the clamp edge's bending starts (update_window); the edge stretches node to
  // node. The rest turns at the clamp vertex and the first free node scaled to the lengths they
  // bend over (hinge_turn_scale_, update_weights).
  double clamp_shift_mm_ = 0.0;
  double hinge_turn_scale_[2] = {1.0, 1.0};
  // hinge_while_drawn_back's word, and that word as taken when the clamp node last changed
  // (update_window): the hinge it adds switches only at a node crossing.
  bool drawn_back_ = false, hinged_back_ = false;
  std::size_t hinged_back_at_kp_ = static_cast<std::size_t>(-1);
  double back_from_mm_ = -std::numeric_limits<double>::infinity();  // update_window's draw-back start
  bool hinge_walking_ = false;  // the hinge walking there: the weights stay the clamp node's (update_weights)

  // Per node.
  std::vector<double> from_tip_, radius_, inner_radius_, ei_, ei_extra_, gj_, voronoi_, drag_per_mm_;
  // soften_joint: the vertex it softens (size_t(-1) for none) and its built EI and GJ.
  std::size_t joint_ = static_cast<std::size_t>(-1);
  double joint_ei_ = 0.0, joint_gj_ = 0.0;
  // Rest curvature towards m1 and m2: 2 tan(phi/2) for the twist coupling, 2 sin(phi/2) for
  // the bending residual (phi = the rest turning angle at the node).
  std::vector<double> kbar1_, kbar2_, kturn1_, kturn2_;
  std::vector<glm::dvec3> twist_load_;  // a released coil's twist on its centreline (add_twist_holonomy_loads)
  // Its stiffness: per vertex i, GJ/l and d(psi_i)/dx at nodes i-1, i, i+1 (3 i .. 3 i + 2), and
  // where the step's solve started (add_twist_stiffness).
  std::vector<double> twist_c_;
  std::vector<glm::dvec3> twist_dpsi_, twist_x0_;
  std::vector<glm::dvec3> x_, x_start_, x_pred_, load_, coupling_, grip_anchor_;
  IndexRange coupling_set_;  // nodes coupling_ may be non-zero at
  IndexRange extra_set_;     // nodes ei_extra_ may be non-zero at
  std::vector<double> grip_limit_;
  std::size_t distal_first_ = std::numeric_limits<std::size_t>::max();  // set_distal_friction
  double distal_mu_ = 0.0;
  std::vector<NodeContact> node_contacts_;
  std::size_t edge_planes_ = 0;  // edges holding a wall plane at the last refresh (rod_edge_wall.cpp)
  // Per edge (k: node k -> k+1).
  std::vector<double> rest_, theta_, theta_start_, ref_twist_;
  std::vector<glm::dvec3> t_, d1_, m1_, m2_;

  // Solver scratch, sized once.
  std::vector<double> grad_, delta_, work_, friction_limit_;
  std::vector<double> plain_delta_;         // the Newton step before predict_edge_contacts
  std::vector<std::uint8_t> predicted_;     // per edge contact: its plane in the step's model
  // Per step: EA / rest per edge, EI / (Voronoi length) per bending vertex, solver drag / dt per
  // free node (update_weights).
  std::vector<double> axial_k_, bend_w_, drag_k_;
  std::vector<std::uint8_t> joined_;  // nodes that joined the active set in this iteration
  std::vector<double> last_step_;  // the last Newton update taken in this step, by unknown
  std::vector<double> held_gap_;      // wall gap of an active node at the end of the Newton step it aims at (half of a damped reversal)
  std::vector<double> tw_diag_, tw_off_, tw_rhs_, tw_inv_;  // twist system; tw_inv_: Thomas' inverse pivots
  std::vector<std::uint8_t> tw_regime_;  // per node: torsional friction off, stick, slip + or slip -
  std::unique_ptr<BandedCholesky> matrix_;

  std::vector<RodContact> contacts_;
  std::vector<EdgeContact> edge_contacts_;
  std::vector<glm::dvec3> gathered_at_;  // node positions when the edge contacts were gathered
  // Warm start (RodSettings::warm_start): each free node's motion in the last step's solve
  // (nodes [warm_first_, n)); warm_ok_ when that solve converged.
  std::vector<glm::dvec3> solved_move_;
  std::size_t warm_first_ = 0;
  bool warm_ok_ = false;
  glm::dvec3 clamp_force_{0.0};
  double hand_force_mN_ = 0.0;
  double clamp_read_mN_ = 0.0;
  // The clamp's force from the rest of a converged step taken in part (linearise_clamp), and
  // whether the last step was one: the hand then reads the moves' clamp plus it.
  std::optional<double> whole_step_extra_mN_;
  std::vector<double> clamp_rows_;     // its scratch: the clamp rows of K_pf (step - moves)
  double hand_torque_mNmm_ = 0.0;
  double free_part_load_mN_ = 0.0;
  ForceLaw law_;
  double energy_ = 0.0;  // energy at the last assembly
  int last_iterations_ = 0;
  int last_substeps_ = 1;
  SolverWork retired_work_;  // of the matrices size_scratch() replaced, and the line-search tries
  std::unique_ptr<StepStart> step_start_;  // made at the first step that keeps it
};

}  // namespace cathbox::tool
