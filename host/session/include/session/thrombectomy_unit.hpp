#pragma once
// Stroke thrombectomy in the session: the case's clots against its aspiration catheter and its
// balloon guide, pass by pass, graded eTICI from the flow network (sim/flow: clot.hpp,
// aspiration.hpp, embolus.hpp, reperfusion.hpp). host/session/README.md, "Thrombectomy".
//
// - Controls: kAspiration (u8 tool, u8 1 on / 0 off) for a catheter the case gives an
//   `aspiration pump|syringe`; kBalloonGuide (u8 tool, u8 1 inflate / 0 deflate) for a
//   catheter with a `balloon`: a FlowArrest on the segment holding its tip (the flow network
//   solved again). Refused (not applied, not recorded, a log line) for another tool, a state it
//   already has, a tip outside the vessels.
// - Engagement: with aspiration on, the catheter's tip within kFaceReach_mm of a clot's
//   proximal face (or inside its span) engages the clot and every clot contiguous with it
//   (a carotid-T thrombus spanning the terminus and its branches is one thrombus).
// - A pass ends when the engaged catheter is withdrawn kPassWithdrawal_mm below its insertion
//   at engagement with aspiration still on. flow::aspirate() with the pressure head across the
//   engaged clot at that moment (lower under flow arrest) decides: ingested or corked, the
//   thrombus leaves with the catheter; lost, it stays, and a fragment the width of the
//   catheter's lumen strips off its face into the flow at its mouth (below). Aspiration off
//   while engaged releases the clot: no pass.
// - Aspiration sinks: an aspirating catheter's open tip (no clot engaged on it) draws blood
//   from the live network (flow::AspirationSink: Poiseuille through its lumen to the vacuum),
//   solved again when a sink's node changes; a fragment at its mouth goes into it when it
//   out-draws every branch there (under flow arrest, the only way out), else the flow takes it.
// - Emboli travel: a fragment released into the flow is a flow::EmbolusTransit advanced every
//   tick in virtual time with the network's flows of the moment (arrested, occluded: the flow
//   model decides whether it moves, and which way) until it lodges where it no longer fits; then
//   it occludes that branch like any clot (a new solve: the fluoroscopy and the grade see it)
//   and counts as an embolus, to a new territory when it starves an outlet outside the target
//   territory. The pass's eTICI is graded again then.
// - While engaged, the vacuum holds the clot on the catheter's tip with |pressure| x lumen area
//   (flow::aspirate, Froehler 2017), and the hand feels it where physical: a clot that corks
//   the tip is dragged with the catheter, which takes what holds the clot in place
//   (flow::clot_hold_force_N); one the vacuum cannot hold (lost) pulls on the tip up to the
//   vacuum's force before the tip comes off it; an ingested clot slides into the lumen and pulls
//   on nothing. That pull is a grip on the catheter's tip node (Simulator::set_tip_grip, set in
//   after_step): an anchor the tip drags once the pull exceeds it.
// - After each pass the network is occluded with what remains (and the emboli) and graded
//   eTICI without the arrest (the control run after deflation), then solved again with any
//   arrest still inflated. Reperfusion = eTICI >= 2b50 (Liebeskind et al., JNIS 2019: the
//   grades; successful reperfusion eTICI >= 2b50).
// - Stent retrievers (a push wire with ToolSpec::stent, tool/stent_retriever.hpp), from the
//   simulator after each step (after_step): expanded (half its length out of the catheters)
//   across a clot it covers, it integrates the clot while it stays (within kStentStill_mm of
//   where it expanded) over its embedding time; withdrawn kStentRetrievalStart_mm the pass
//   begins: the stent holds the thrombus when its grip (integration x the share of the
//   thrombus it covers x its capture force) exceeds what holds the thrombus in place
//   (flow::clot_hold_force_N with the head across it), and then drags it (its kinetic wall
//   friction and the head, felt at the hand through the simulator's stent payload). The pass
//   ends when the stent is back in a catheter: in the guide or aspiration catheter the clot
//   comes out with it; wider than that catheter's lumen, the rim the mouth shears off (d - ID
//   wide) goes into the flow at its mouth (an aspirating catheter's sink may draw it in), except
//   under flow arrest without aspiration (a rule: it stays in the arrested column); re-sheathed in its microcatheter the clot, stripped off the struts at that tip, is
//   released into the flow there, in the pieces the flow's shear tears it into
//   (flow::fragments_in_flow: at arterial shear, whole); not held, it stays. The pass is graded as an aspiration pass, and the
//   peak pull on the push wire during it is the retrieval force.
// All of this runs on the haptic thread between ticks; a pass re-solves the network (~10 µs,
// sim/flow bench_flow BM_Occlude) and allocates: an event, like a coil's release.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "flow/aspiration.hpp"
#include "flow/centerline_locator.hpp"
#include "flow/clot.hpp"
#include "flow/embolus.hpp"
#include "flow/flow_network.hpp"
#include "flow/reperfusion.hpp"
#include "session/control.hpp"
#include "session/metrics.hpp"
#include "session/scene_snapshot.hpp"
#include "session/vacuum_hold.hpp"
#include "scenario/case_file.hpp"
#include "tool/simulator.hpp"
#include "tool/snapshot.hpp"

namespace cathbox::session {

class EventLog;

inline constexpr double kFaceReach_mm = 2.0;
inline constexpr double kStentStill_mm = 1.0;
inline constexpr double kStentRetrievalStart_mm = 2.0;

class ThrombectomyUnit final : public ControlHandler {
 public:
  static constexpr std::array<ControlKind, 2> kKinds{ControlKind::kAspiration, ControlKind::kBalloonGuide};

  // `network` is the case's, occluded by its clots (load_session_case); kept by reference.
  // Null when the case has no clot or the occlusion starves no outlet (nothing to grade).
  [[nodiscard]] static std::unique_ptr<ThrombectomyUnit> make(flow::FlowNetwork& network, const tool::Case& spec,
                                                              EventLog& events, std::string& why_not);

  bool apply(Control& control, ControlContext& context) override;
  // What the two controls do (false: refused, logged, nothing changed), at `time_us`.
  bool set_aspiration(std::size_t tool, bool on, std::int64_t time_us);
  bool set_balloon_guide(std::size_t tool, bool inflate, std::int64_t time_us);
  // After each step: engagement and the end of a pass, from the tools' tips and insertions.
  void tick(std::int64_t time_us, const tool::Snapshot& snapshot);
  // After each step, the stent retrievers (their state from the simulator; the clot they drag
  // is set as their payload there for the next step).
  void after_step(std::int64_t time_us, tool::Simulator& sim);
  // The pull, mN, the engaged clot puts on aspiration catheter `tool`'s tip now (0 when it is
  // not engaged, or the clot would be ingested): min(vacuum force, the clot's hold).
  [[nodiscard]] double aspiration_grip_mN(std::size_t tool) const;
  // The pull, mN, on the push wire of a stent retriever being retrieved, as of the last
  // after_step (the largest of them): the hand force of a converged step, 0 when no stent is
  // being retrieved or its step did not converge. Its peak over a pass is that pass's
  // retrieval force (ThrombectomyFigures::retrieval_force_peak_N, counted when the pass ends).
  [[nodiscard]] double retrieval_pull_mN() const { return retrieval_pull_mN_; }
  // The integrated share of the clot under a stent tool (0 when none is deployed across one).
  [[nodiscard]] double stent_integration(std::size_t tool) const;
  // Stent tool `tool`'s retrieval pass is running (begun, not yet back in a catheter).
  [[nodiscard]] bool stent_retrieving(std::size_t tool) const;
  [[nodiscard]] const ThrombectomyFigures& figures() const { return figures_; }
  [[nodiscard]] bool aspirating(std::size_t tool) const { return tool < aspirating_.size() && aspirating_[tool] != 0; }
  [[nodiscard]] bool arrested() const { return !arrests_.empty(); }
  // The case's first aspiration catheter and first catheter with a balloon (the trainer's keys).
  [[nodiscard]] std::optional<std::size_t> first_aspirator() const {
    return aspirators_.empty() ? std::nullopt : std::optional<std::size_t>(aspirators_.front().tool);
  }
  [[nodiscard]] std::optional<std::size_t> first_balloon_guide() const;
  // Counts the network's solves since load (a pass, an arrest): the fluoroscopy follows it.
  [[nodiscard]] std::uint64_t flow_generation() const { return flow_generation_; }
  [[nodiscard]] bool engaged() const { return hold_.tool().has_value(); }
  [[nodiscard]] const std::vector<flow::Clot>& clots() const { return clots_; }
  // Clot `k` (k < clots().size()) as the views draw it, as of the last tick: in place along its
  // vessel's centreline; dragged, along the stent's path, where it lay on the stent's nodes when
  // the retrieval began (the nodes are material points: it rides with them round bends).
  [[nodiscard]] ClotView clot_view(std::size_t k) const;
  [[nodiscard]] int clots_removed() const { return clots_removed_; }
  // Emboli released and not yet lodged (travelling, or stalled where no flow carries them).
  [[nodiscard]] std::size_t emboli_in_transit() const { return in_transit_.size(); }
  // Embolus `k` in transit (k < emboli_in_transit()) as the 3D view draws it (kInTransit): a body
  // of its diameter along its segment's centreline, its length behind its leading point (the
  // way the flow carries it), within that segment.
  [[nodiscard]] ClotView embolus_view(std::size_t k) const;
  // The run ends at `time_us`: each embolus still in transit is counted (figures().emboli, and
  // emboli_new_territory if it would starve a new territory) and described (emboli_in_transit):
  // its transit continued to its end in the network without any arrest (the guide comes out
  // with the procedure), the fragments before it lodged as clots, each lodging tried against the
  // network without it. The grade is not changed (the final angiogram does not show a fragment
  // still on its way). The network is left as it was. Once per run; a second call does nothing.
  void finish(std::int64_t time_us);

 private:
  ThrombectomyUnit(flow::FlowNetwork& network, EventLog& events, flow::TargetTerritory target);
  void log(std::int64_t time_us, const char* fmt, ...) __attribute__((format(printf, 3, 4)));
  // The ids of clot `clot` (an index in clots_) and the clots contiguous with it, it first.
  [[nodiscard]] std::vector<ClotId> thrombus_of(std::size_t clot) const;
  // Clots by id (clot_ids_ beside clots_): a remaining clot, an embolus lodged, those a pass took out.
  [[nodiscard]] std::optional<std::size_t> index_of(ClotId id) const;
  [[nodiscard]] const flow::Clot& clot_of(ClotId id) const { return clots_[*index_of(id)]; }
  [[nodiscard]] bool all_remain(const std::vector<ClotId>& ids) const;
  void add_clot(const flow::Clot& c);
  void erase_clots(std::span<const ClotId> ids);
  [[nodiscard]] const Aspirator* aspirator(std::size_t tool) const;
  [[nodiscard]] std::optional<std::size_t> clot_at_tip(const glm::dvec3& tip_mm) const;
  void end_pass(std::int64_t time_us);
  // A pass's grading after `removed` (may be empty) left and a fragment (if any) was carried:
  // the control run, the embolus, eTICI and the figures. A vacuum held on a removed clot lets go.
  void grade_pass(std::int64_t time_us, const std::vector<ClotId>& removed, const std::vector<flow::Fragment>& fragments);
  // The figures of the last pass from the network as it is now (control run, no arrest).
  void regrade(std::int64_t time_us);
  // Emboli (thrombectomy_emboli.cpp): fragments into the flow, moved on each tick, lodged.
  void release(std::int64_t time_us, const std::vector<flow::Fragment>& fragments);
  void carry_emboli(std::int64_t time_us);
  void settle(std::int64_t time_us, const flow::EmbolusTransit& transit);
  void lodge(std::int64_t time_us, const flow::EmbolusTransit& transit);
  // The head across a clot (its segment's end pressures) and the clot as the aspiration model sees it.
  [[nodiscard]] double head_Pa(const flow::Clot& c) const;
  [[nodiscard]] flow::AspirationClot thrombus_clot(const std::vector<ClotId>& group) const;
  struct StentPass;
  struct StentCover {
    std::vector<ClotId> thrombus;       // the first clot under the stent and its thrombus
    double share = 0.0;                 // of the thrombus's length under the stent
  };
  [[nodiscard]] StentCover stent_cover(const tool::Simulator& sim, std::size_t tool) const;
  void stent_step(StentPass& p, std::int64_t time_us, tool::Simulator& sim);
  void deploy_stent(StentPass& p, std::int64_t time_us, const tool::Simulator& sim);
  void start_retrieval(StentPass& p, std::int64_t time_us, tool::Simulator& sim);
  void end_stent_pass(StentPass& p, std::int64_t time_us, tool::Simulator& sim);
  void hold_on_stent(StentPass& p, std::span<const glm::dvec3> x) const;
  // Occludes with clots_, and when `live` with arrests_ and sinks_ (else the control run's
  // network); false (logged) when the network refuses.
  bool resolve(std::int64_t time_us, bool live);
  // The aspirating catheters' open tips (not on an engaged clot) in the vessels, as sinks.
  [[nodiscard]] std::vector<flow::AspirationSink> live_sinks(std::vector<std::size_t>* tools = nullptr) const;
  // Solves the live network again when the sinks' nodes changed (aspiration on/off, a tip
  // moved to another node, engaged or let go).
  void update_sinks(std::int64_t time_us);
  // Where a fragment at tool `t`'s mouth starts: its sink's node when it aspirates, else its tip.
  [[nodiscard]] flow::CenterlinePosition mouth(std::size_t t) const;
  [[nodiscard]] std::string segment_name(std::uint32_t segment) const;

  flow::FlowNetwork& network_;
  EventLog& events_;
  flow::TargetTerritory target_;
  flow::CenterlineLocator locator_;
  std::vector<flow::Clot> clots_;        // what remains, emboli included
  std::vector<ClotId> clot_ids_;         // of each of clots_
  ClotId next_clot_id_ = 0;
  std::vector<flow::FlowArrest> arrests_;
  std::vector<flow::AspirationSink> sinks_;  // as the live network was last solved
  std::vector<std::size_t> arrest_tool_;  // the tool of each arrest
  std::int64_t arrest_since_us_ = -1;      // when the first of the inflated guides went up (-1: none)
  std::int64_t arrest_before_us_ = 0;      // arrest time of the arrests already over
  std::vector<Aspirator> aspirators_;        // by tool
  std::vector<std::uint8_t> aspirating_;     // per tool
  std::vector<std::uint8_t> balloon_;        // per tool: carries a balloon (a balloon guide)
  std::vector<double> inner_diameter_;       // per tool (0: none)
  std::vector<std::string> tool_names_;
  std::vector<glm::dvec3> tips_;             // per tool, as of the last tick
  VacuumHold hold_;  // the engaged thrombus
  // Stent retrievers, by tool.
  struct StentPass {
    std::size_t tool = 0;
    tool::StentRetrieverSpec spec;
    bool deployed = false;        // expanded across a clot
    bool retrieving = false;
    bool captured = false;
    std::vector<ClotId> thrombus;
    double cover = 0.0;           // the share of the thrombus's length under the stent
    double deployed_insertion_mm = 0.0;
    double dwell_s = 0.0;
    double integration = 0.0;
    double peak_pull_mN = 0.0;
    std::int64_t last_us = -1;
    double tried_unsheathed_mm = -1e9;  // where a deployment over no clot was last looked at
    double tried_insertion_mm = -1e9;
    // While it drags its clot: the stent tool's distal nodes (tip last), as of the last tick, and
    // per clot of the thrombus its face and end as node parameters from the tip (j + f: between
    // the j-th and (j+1)-th node back from the tip).
    std::vector<glm::dvec3> path;
    std::vector<std::array<double, 2>> on_stent;
  };
  std::vector<StentPass> stents_;
  double retrieval_pull_mN_ = 0.0;  // retrieval_pull_mN()
  std::vector<flow::EmbolusTransit> in_transit_;  // emboli on their way
  std::int64_t last_tick_us_ = -1;
  bool finished_ = false;
  std::int64_t pass_end_us_ = -1;  // when the last pass ended
  ThrombectomyFigures figures_;
  std::uint64_t flow_generation_ = 0;
  int clots_removed_ = 0;
};

}  // namespace cathbox::session
