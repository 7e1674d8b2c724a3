#pragma once
// The tools in the vessel: elastic rods (guidewires, catheters, coils on their pushers,
// balloon catheters), each driven at the entry by its own insertion and rotation, nested to
// any depth (guide catheter > microcatheter > microwire), stepped in virtual time. The caller
// drives time (one step() per haptic tick) and owns the wall.
//
// Nested tools follow the composite model of Lenoir, Cotin, Duriez, Neumann, "Interactive
// physically-based simulation of catheter and guidewire", Computers & Graphics 30(3), 2006:
// where a tool runs inside catheters it lies on their centre line and they bend with the sum
// of the stiffnesses; the part of a tool beyond the furthest tip of the catheters around it is
// its own rod clamped at that tip; a catheter advanced over a tool is predicted along that
// tool's path. The friction of each tool in the lumens around it is felt at its hand and drags
// the catheters (SheathFriction). Coils leave their microcatheter taking their secondary shape,
// touch themselves, earlier coils and the microcatheter's tip (RodContactField), and are
// released by detach(). Balloons inflate along a compliance curve (Balloon), grip the wall
// while inflated, and hold the coils off with their working length (RodContactField).
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tool/balloon.hpp"
#include "tool/coil_sleep.hpp"
#include "tool/rod.hpp"
#include "tool/rod_contact_field.hpp"
#include "tool/sheath_friction.hpp"
#include "tool/stent_retriever.hpp"
#include "tool/snapshot.hpp"
#include "tool/valve_friction.hpp"
#include "tool/wall_model.hpp"

namespace cathbox::tool {

struct Entry {
  glm::dvec3 point_mm{0.0};
  glm::dvec3 direction{0.0, 0.0, 1.0};
};

// Why a device action was refused (nothing changed then).
enum class DeviceError : std::uint8_t {
  kNone = 0,
  kNoSuchTool,
  kNotACoil,          // detach on a tool that carries no coil (or already released it)
  kCoilInCatheter,    // detach while the detachment zone is still inside the catheter
  kNotABalloon,       // inflate/deflate on a tool without a balloon
  kOutOfRange,        // pressure or volume outside what the balloon takes
  kCoilAttached,      // load_next_coil while the loaded coil is not released yet
  kNoNextCoil,        // load_next_coil on a coil tool whose case lists no further coil
};
[[nodiscard]] const char* device_error_text(DeviceError e);

class BackgroundJob;

class Simulator {
 public:
  // `wall` must outlive the simulator (or its replacement, see swap_wall). Inner tools name
  // the catheter they run in in ToolSpec::inside (any depth; no cycles).
  Simulator(const WallModel& wall, std::span<const ToolSpec> tools, const Entry& entry,
            const RodSettings& settings = {});
  ~Simulator();
  Simulator(Simulator&&) noexcept;
  Simulator& operator=(Simulator&&) noexcept;

  [[nodiscard]] std::size_t tool_count() const { return rods_.size(); }
  // A tool's solver settings, to change after construction (compliant_contact.hpp).
  [[nodiscard]] RodSettings& rod_settings(std::size_t tool) { return rods_[tool].settings(); }
  [[nodiscard]] std::size_t find_tool(std::string_view name) const;  // tool_count() if none
  void select(std::size_t tool);
  [[nodiscard]] std::size_t active_tool() const { return active_; }
  // The catheter a tool runs in, or tool_count() for a tool in the vessel.
  [[nodiscard]] std::size_t outer_of(std::size_t tool) const { return outer_of_[tool]; }

  // Box input for one tool (the active one on a real box).
  void set_insertion(std::size_t tool, double insertion_mm);
  void set_rotation(std::size_t tool, double rotation_rad);
  [[nodiscard]] double insertion_mm(std::size_t tool) const { return insertion_[tool]; }
  [[nodiscard]] double rotation_rad(std::size_t tool) const { return rotation_[tool]; }
  // Largest insertion the box may command (the tool's length, less a released coil).
  [[nodiscard]] double max_insertion_mm(std::size_t tool) const;

  // Test hook: a constant force on one node of a tool (e.g. a load resisting its tip).
  void set_node_load(std::size_t tool, std::size_t node, const glm::dvec3& force_mN) {
    if (tool < rods_.size()) rods_[tool].set_node_load(node, force_mN);
  }

  // Advances the simulation by dt seconds (1 ms at haptic rate). With released_overlap() it
  // may return with the released coils' solve still running (below).
  void step(double dt_s = 1e-3);
  // Called at the start of each step(), once no solve runs, before anything reads the wall: the
  // owner's changes to a wall the simulator holds that move it in place (a DisplacedWall's pulse)
  // go here when the released coils' solve may outlast the step (released_overlap).
  void set_before_solves(std::function<void()> fn) { before_solves_ = std::move(fn); }

  [[nodiscard]] double time_s() const { return time_s_; }
  [[nodiscard]] std::uint64_t steps() const { return steps_; }
  [[nodiscard]] const Rod& rod(std::size_t tool) const { return rods_[tool]; }
  [[nodiscard]] std::int32_t tip_segment(std::size_t tool) const { return tip_segment_[tool]; }
  [[nodiscard]] double hand_force_mN(std::size_t tool) const;
  [[nodiscard]] double hand_torque_mNmm(std::size_t tool) const;
  [[nodiscard]] ForceLaw force_law(std::size_t tool) const;
  [[nodiscard]] TipPose tip(std::size_t tool) const { return rods_[tool].tip(); }
  // The push the tools a catheter carries put on its tip node (steering; zero on a tool that
  // carries none or is not steered): lagged a step, relaxed, its change bounded.
  [[nodiscard]] glm::dvec3 tip_push_mN(std::size_t tool) const { return tip_push_[tool]; }
  // Depth past the entry of a tool's tip, and where its own (simulated) part begins: the
  // furthest tip of the catheters around it (0 for a tool in the vessel).
  [[nodiscard]] double tip_depth_mm(std::size_t tool) const;
  [[nodiscard]] double free_start_mm(std::size_t tool) const { return free_start_[tool]; }
  // Friction of the catheters around a tool in the last step (zero for a tool in the vessel).
  [[nodiscard]] const SheathFriction::Result& sheath(std::size_t tool) const { return sheath_result_[tool]; }
  // Friction of the haemostatic valve the tool slides through, last step (in hand_force_mN).
  [[nodiscard]] const ValveFriction::Result& valve(std::size_t tool) const { return valve_result_[tool]; }
  // Inserted node positions of a tool, entry to tip, the part inside catheters included.
  void inserted_positions(std::size_t tool, std::vector<glm::dvec3>& out) const;

  // Coils. Starts the release of the coil of `tool` at its detachment zone, which must be out of
  // the catheter: the zone parts over tuning::kDetachParting_s (its joint's bending and twisting
  // stiffness falling with its section, advance_partings), then the coil is released. A zone
  // drawn back into the catheter before it parts stays whole (parting() goes false, unreleased).
  [[nodiscard]] DeviceError detach(std::size_t tool);
  // `tool`'s detachment zone is parting (detach started, the coil not released yet).
  [[nodiscard]] bool parting(std::size_t tool) const;
  [[nodiscard]] std::size_t detached_count() const { return detached_.size(); }
  // Released coil i, its solve over (settle()): its solver's state as well as its results.
  [[nodiscard]] const Rod& detached(std::size_t i) const {
    settle_now();
    return detached_[i];
  }
  // Released coil i as its last finished solve left it, never waiting for one: its nodes, radii,
  // arc lengths, tangents, directors, wall contacts and convergence (Rod::mirror_published_view).
  // With released_overlap() a coil whose solve runs beside the caller reads as it was when the
  // step began (one step behind detached(i)); otherwise the same as detached(i).
  [[nodiscard]] const Rod& released_view(std::size_t i) const { return coil_views_[i]; }
  // Length of coil released from `tool` (its present coil) so far (0 before detach).
  [[nodiscard]] double released_mm(std::size_t tool) const { return removed_mm_[tool]; }
  // After detach: the old pusher is withdrawn and the tool's next coil (ToolSpec::next_coils,
  // in order) is fed into the catheter's hub on a new pusher: the tool becomes that coil on its
  // pusher at insertion 0 and rotation 0. Allocates (a new rod): an event, not every tick.
  [[nodiscard]] DeviceError load_next_coil(std::size_t tool);
  // Coils loaded after the first on `tool` so far.
  [[nodiscard]] std::size_t coils_loaded(std::size_t tool) const { return loaded_[tool]; }
  // `tool` carries a coil not released yet (detach may release it once it is out of the catheter).
  [[nodiscard]] bool carries_attached_coil(std::size_t tool) const;
  // `tool` is a coil tool whose case lists a coil not loaded yet (load_next_coil loads it once
  // the present coil is released).
  [[nodiscard]] bool has_next_coil(std::size_t tool) const;
  // Deepest overlap between coil loops (and coils and the microcatheter tip), last step.
  [[nodiscard]] RodContactField::Overlap worst_coil_overlap() const { return contacts_.worst_overlap(); }
  // Released coils at rest are not solved while nothing near them moves (coil_sleep.hpp); its
  // settings may be changed between steps (enabled = false solves every coil every step).
  [[nodiscard]] const CoilSleep& coil_sleep() const { return sleep_; }
  [[nodiscard]] CoilSleep::Settings& coil_sleep_settings() { return sleep_.settings(); }
  // Released coils are solved on every `ticks`-th step, over that many steps' time, taking turns
  // (tuning::kReleasedCoilTicks by default; 1 solves every coil every step). Tests and benches.
  void set_released_turn_ticks(int ticks) {
    settle();
    released_turn_ = ticks > 1 ? static_cast<std::size_t>(ticks) : 1;
  }
  [[nodiscard]] std::size_t released_turn_ticks() const { return released_turn_; }
  // Released coil i is solved in the next step() (its turn: step + i a multiple of the turn).
  [[nodiscard]] bool released_coil_turn(std::size_t i) const { return (steps_ + i) % released_turn_ == 0; }
  // The released coils on their turn are solved on a thread of their own while step() solves
  // the attached tools, each from where the step began (launch_released). Off: solved on the
  // calling thread at the same point, from the same state: the same results, bit for bit. On
  // by default with two or more cores (off in the WebAssembly build).
  void set_released_in_parallel(bool on);
  [[nodiscard]] bool released_in_parallel() const;
  // Overlap (off by default; the session's haptic loop turns it on): step() returns as soon as
  // the attached tools are solved, the released coils' job still running, and the next step()
  // (or settle(), or any call that needs them: detached(), swap_wall() ...) takes its results in
  // first, at that fixed point: the same results, bit for bit. Between the two, released_view()
  // and copy_snapshot() read the coils as the step began. The job runs in the time the haptic
  // loop would sleep until its next tick. A simulator with a job running is not to be moved.
  void set_released_overlap(bool on);
  [[nodiscard]] bool released_overlap() const { return overlap_; }
  // Waits for a released coils' job a step left running and takes its results in (at once when
  // none runs).
  void settle();
  // Work the next step would do that the caller may do now, while it waits for the next tick (the
  // session's haptic loop, after the hand has its force): the attached tools' candidate list of
  // rod contacts built again once an edge has moved most of the way it covers, instead of in the
  // next step's solve. The results are the same, bit for bit, whether or not it is called; it
  // leaves the released coils' job running. True when it did work.
  bool prepare_next_step();
  // The last step's released-coil job, in microseconds of the steady clock (for benches): how
  // long it ran, and how long the step then waited for it (0 when it was over first, inline,
  // or when no released coil was solved).
  struct ReleasedTiming {
    double run_us = 0.0, wait_us = 0.0;
  };
  [[nodiscard]] ReleasedTiming released_timing() const { return released_timing_; }
  // The rod-rod contact field (its candidate-list builds, for benches).
  [[nodiscard]] const RodContactField& coil_contacts() const { return contacts_; }
  // The released coils' own field (launch_released), for benches.
  [[nodiscard]] const RodContactField& released_contacts() const {
    settle_now();
    return released_contacts_;
  }
  // Told of each rod solve as step() makes it (a tool's, or a released coil's on its turn), for
  // benches that attribute a tick's time to its solves (bench/session's CaseAtRigSpeed). It
  // only reads; null (the default) costs a test per solve.
  class SolveObserver {
   public:
    virtual ~SolveObserver() = default;
    virtual void step_begins() {}
    virtual void solved(bool released, std::size_t index, const Rod& rod) = 0;
  };
  void set_solve_observer(SolveObserver* observer) { observer_ = observer; }

  // Balloons: the inflation device drives the pressure towards the target at its rate.
  [[nodiscard]] DeviceError inflate_pressure(std::size_t tool, double pressure_atm);
  [[nodiscard]] DeviceError inflate_volume(std::size_t tool, double volume_ml);
  [[nodiscard]] DeviceError deflate(std::size_t tool);
  [[nodiscard]] const Balloon* balloon(std::size_t tool) const;
  // Balloon axis points (proximal to distal) and their inflated radius, in the last step.
  void balloon_axis(std::size_t tool, std::vector<glm::dvec3>& points_mm) const;

  // Stent retrievers (ToolSpec::stent): null for a tool without one. The state is the last
  // step's (unsheathed length, radial force, expanded diameters).
  [[nodiscard]] const StentRetriever* stent(std::size_t tool) const {
    return tool < stents_.size() && stents_[tool] ? &*stents_[tool] : nullptr;
  }
  // An added grip on the unsheathed stent, spread by length (an integrated clot dragged along
  // the wall: its friction, set by the owner), from the next step; 0 removes it.
  void set_stent_payload(std::size_t tool, double payload_mN) {
    if (tool < stents_.size() && stents_[tool]) stents_[tool]->set_payload_mN(payload_mN);
  }
  // A grip on the tool's tip node, from the next step, while that node is out of every catheter
  // (a clot corked in an aspiration catheter's tip, held there by the vacuum: what it takes to
  // drag the clot, or to pull the tip off it, set by the owner); 0 releases it.
  void set_tip_grip(std::size_t tool, double grip_mN) {
    if (tool < tip_grip_.size()) tip_grip_[tool] = std::isfinite(grip_mN) && grip_mN > 0.0 ? grip_mN : 0.0;
  }
  [[nodiscard]] double tip_grip_mN(std::size_t tool) const { return tool < tip_grip_.size() ? tip_grip_[tool] : 0.0; }
  // The catheter whose tip the tool's free part starts at (tool_count() for a tool in the vessel).
  [[nodiscard]] std::size_t carrier(std::size_t tool) const { return carrier_[tool]; }

  // The wall, and its replacement between two steps (a widened lumen): the old wall is
  // returned to the caller, which must keep it alive until this returns and then destroy it
  // off the haptic thread. Costs nothing here; every node is probed afresh in the next step.
  [[nodiscard]] const WallModel& wall() const { return *wall_; }
  const WallModel* swap_wall(const WallModel& next);
  [[nodiscard]] std::uint64_t wall_swaps() const { return wall_swaps_; }

  void copy_snapshot(Snapshot& out) const;

 private:
  void update_chain();
  void prepare(std::size_t tool);
  void update_contact_members();
  void add_balloon_members();
  [[nodiscard]] bool lone(std::size_t t) const;  // no catheter around it, none inside it, not a coil
  [[nodiscard]] bool hinged_at_entry(std::size_t t) const;  // RodSettings::clamp_hinge_at_entry for tool t
  [[nodiscard]] bool drawn_back_wire(std::size_t t) const;  // Rod::hinge_while_drawn_back for tool t
  [[nodiscard]] bool push_bounded(std::size_t c) const;  // carrier c's tip push is slew-limited (limit_tip_push)
  // Whether tool t's unconverged tick is solved again in sub-increments this step.
  [[nodiscard]] bool substepped(std::size_t t) const;
  [[nodiscard]] bool unsheathing(std::size_t u) const;  // stent u part out of its catheters, part in
  [[nodiscard]] bool balloon_guide(std::size_t c) const;  // c is outermost and a balloon catheter (kAlways)
  void update_sheath(std::size_t tool, double dt_s);
  void limit_tip_push();
  void hold_unconverged();  // an unconverged tick's hand force and law: the last converged tick's
  // Whether carrier `c`'s tip follows the tools it carries this step (ToolSpec::steered_by_inner).
  [[nodiscard]] bool steered_now(std::size_t c) const;
  [[nodiscard]] bool drawn_back_into(std::size_t c) const;  // a wire or catheter leaving c's tip is drawn back this step
  [[nodiscard]] bool leaves_tip(std::size_t u) const;  // tool u has a free part beyond its carrier's tip
  [[nodiscard]] bool tip_lean_held(std::size_t c) const;  // c's steering push kept as it is this step
  void build_sheath_path(std::size_t tool, std::vector<SheathVertex>& path) const;
  static void cover_sheath_path(const Rod& inner, double tip_mm, double end_mm, std::vector<SheathVertex>& path);
  [[nodiscard]] bool nested_in(std::size_t inner, std::size_t outer) const;
  [[nodiscard]] glm::dvec3 path_point(std::size_t tool, double depth_mm) const;
  void fill_tool_snapshot(const Rod& rod, ToolSnapshot& s) const;
  void update_balloons(double dt_s);
  void update_stents();
  void update_tip_grips();
  void solve_tool(std::size_t t, double dt_s, bool released);
  void launch_released(double dt_s);
  void finish_released();
  // settle() for the readers of what the job writes (a Simulator is never defined const).
  void settle_now() const {
    if (pending_) const_cast<Simulator*>(this)->finish_released();  // NOLINT(cppcoreguidelines-pro-type-const-cast)
  }
  static void solve_released(void* simulator);  // the job: BackgroundJob's thread, or inline
  [[nodiscard]] const Rod* job_rod(const Rod* rod, bool refresh);  // simulator_released.cpp
  void advance_partings(double dt_s);
  void release_coil(std::size_t tool);
  [[nodiscard]] bool zone_out(std::size_t tool) const;  // its coil's detachment zone is past the catheter's tip
  void apply_coil_settings(std::size_t coil);

  const WallModel* wall_;
  Entry entry_;
  RodSettings settings_;
  std::vector<Rod> rods_;
  std::vector<std::size_t> outer_of_;  // index of the catheter around it, or tool_count() if none
  std::vector<std::size_t> order_;     // outer tools first
  std::vector<double> insertion_, rotation_, stepped_depth_, stepped_rotation_, removed_mm_, free_start_;
  // Each tool's insertion at the end of its last step, and how far it moved and turned in it (force_law:
  // an anchor on a catheter that moved is not a spring fixed in the box's frame).
  std::vector<double> stepped_insertion_, moved_mm_, turned_rad_;
  std::vector<std::size_t> carrier_;   // the catheter whose tip the tool's free part starts at
  std::vector<std::int32_t> tip_segment_;
  std::vector<WallHint> tip_hint_;
  std::vector<double> extra_ei_;       // scratch for the composite stiffness
  std::vector<SheathFriction> sheath_;
  std::vector<SheathFriction::Result> sheath_result_;
  std::vector<SheathVertex> path_;     // scratch
  std::vector<std::vector<glm::dvec3>> coupling_next_;  // loads for the next step, per tool node
  std::vector<IndexRange> coupling_set_;                 // nodes of each coupling_next_ ever loaded
  std::vector<glm::dvec3> tip_push_;  // per tool: the tools it carries pushing on its tip node, relaxed
  std::vector<glm::dvec3> tip_push_before_;  // scratch: tip_push_ at the start of the step
  // Per carrier whose push is slew-limited: the push's last change, and the share of the slew it
  // may change by this step (limit_tip_push: halved where the push reverses, regrown where not).
  struct PushSlew {
    glm::dvec3 last{0.0};
    double share = 1.0;
  };
  std::vector<PushSlew> push_slew_;
  std::vector<glm::dvec3> converged_clamp_;  // per tool: its clamp force at its last converged step
  std::vector<double> hand_force_, hand_torque_;
  // Per tool: its force law at its last converged tick (none before one), and whether this tick's
  // hand force and law are held to it (hold_unconverged).
  std::vector<std::optional<ForceLaw>> converged_law_;
  std::vector<std::uint8_t> held_;
  std::vector<ValveFriction> valve_;
  std::vector<ValveFriction::Result> valve_result_;
  std::vector<std::optional<Balloon>> balloons_;
  bool balloon_moved_ = false;         // some balloon's pressure changed in this step
  std::vector<std::optional<StentRetriever>> stents_;
  std::vector<double> tip_grip_;       // per tool, mN (set_tip_grip)
  std::vector<Rod> detached_;
  // Per tool: how long its detachment zone has been parting (detach), negative while none does.
  std::vector<double> parting_s_;
  std::vector<ToolSpec> specs_;        // the tools as the case gives them (next coils included)
  std::vector<std::size_t> loaded_;    // next coils loaded per tool
  RodContactField contacts_;
  CoilSleep sleep_;
  std::size_t released_turn_;  // tuning::kReleasedCoilTicks by default
  std::uint64_t wall_revision_ = 0;  // the wall's revision() the coils last slept against
  std::vector<RodContactField::Member> members_;  // scratch
  std::size_t active_ = 0;
  double time_s_ = 0.0;
  std::uint64_t steps_ = 0;
  std::uint64_t wall_swaps_ = 0;
  SolveObserver* observer_ = nullptr;
  // The released coils' solve beside the attached tools' (launch_released): per released coil
  // and per tool, a view of it as the step began (Rod::contact_view_of): the attached tools'
  // field and the sleep read the coils' views, the coils' own field the tools' views.
  std::vector<Rod> coil_views_, tool_views_;
  RodContactField released_contacts_;
  std::vector<RodContactField::Member> released_members_;  // scratch
  std::vector<std::size_t> solving_;  // the released coils this step's job solves
  ReleasedTiming released_timing_;
  double released_dt_s_ = 0.0;
  std::unique_ptr<BackgroundJob> job_;
  bool overlap_ = false;              // set_released_overlap
  bool pending_ = false;              // a step's released coils not taken in yet (finish_released)
  std::uint64_t launched_step_ = 0;   // that step's number (whose coils were on their turn)
  std::function<void()> before_solves_;
};

}  // namespace cathbox::tool
