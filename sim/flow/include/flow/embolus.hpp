#pragma once
// A clot fragment carried by the blood: from where it breaks off it follows the flow (at each
// junction into the branch that takes the most flow away from it, the likeliest path) until it
// reaches a lumen narrower than itself, where it lodges as a new clot occluding that branch;
// a fragment that reaches an outlet lodges at the outlet's end (beyond the model, in that
// territory). An embolus to a new territory (ENT) is one whose clot starves an outlet outside
// the target territory (reperfusion.hpp).
//
// In time (`EmbolusTransit`): the fragment moves at the cross-section mean velocity of the
// lumen it is in, |Q| / (pi r^2), in the network's flows of the moment, so it crosses a piece of
// lumen in (its volume) / |Q|: a path of volume V takes V / Q, L / v for a uniform tube. It goes
// the way the flow goes: backwards in a reversed segment, nowhere where there is no flow (it
// waits, stalled, for the flow to resume). At a node where an aspiration catheter's open tip
// draws more flow than any branch takes away (FlowNetwork's sinks), it goes into the catheter.
#include <cstdint>
#include <vector>

#include "base/result.hpp"
#include "flow/centerline_locator.hpp"
#include "flow/flow_network.hpp"
#include "flow/reperfusion.hpp"

namespace cathbox::flow {

struct Fragment {
  CenterlinePosition from;   // where it breaks off
  double diameter_mm = 1.5;  // as it travels (its unloaded diameter)
  double length_mm = 3.0;
  ClotComposition composition;
};

struct EmbolusPath {
  Clot lodged;                          // where it stops, as a clot (open fraction 0)
  std::vector<std::uint32_t> segments;  // segments it travelled, in order
  bool at_outlet = false;               // it reached an outlet of the model
  bool aspirated = false;               // an aspiration catheter's tip drew it in (lodged: unset)
};

enum class TransitState : std::uint8_t {
  kTravelling,  // moving with the flow
  kStalled,     // no flow where it is (it moves on when the flow resumes)
  kLodged,      // stopped where the lumen is narrower than it: path().lodged
  kAtOutlet,    // reached an outlet of the model: path().lodged at its end
  kAspirated,   // reached a node where an aspiration sink draws more than any branch: in the catheter
};

// A fragment on its way, advanced in time by the caller (virtual time).
class EmbolusTransit {
 public:
  // An error for a bad fragment (segment, sizes, composition).
  [[nodiscard]] static base::Result<EmbolusTransit> start(const FlowNetwork& network, const Fragment& fragment);
  // Moves it `dt_s` on in `network`'s current flows (the network it started in, maybe occluded
  // or arrested since). Returns the state it ends in; a lodged fragment moves no more.
  TransitState advance(const FlowNetwork& network, double dt_s);

  [[nodiscard]] TransitState state() const { return state_; }
  [[nodiscard]] bool done() const { return state_ != TransitState::kTravelling && state_ != TransitState::kStalled; }
  [[nodiscard]] CenterlinePosition position() const { return {seg_, arc_mm_, 0.0}; }
  [[nodiscard]] double elapsed_s() const { return elapsed_s_; }        // time advanced until it stopped
  [[nodiscard]] double travelled_mm() const { return travelled_mm_; }  // along the centrelines
  [[nodiscard]] const Fragment& fragment() const { return fragment_; }
  [[nodiscard]] const EmbolusPath& path() const { return path_; }

 private:
  EmbolusTransit() = default;
  // One move within the current segment or across its end; the time it took (<= budget_s).
  double move(const FlowNetwork& network, double budget_s, double noise);
  void enter(const FlowNetwork& network, std::uint32_t segment, double arc_mm);
  void aspirate_at_start(const FlowNetwork& network);

  Fragment fragment_;
  std::uint32_t seg_ = 0;
  double arc_mm_ = 0.0;
  std::vector<double> arcs_;  // the current segment's point arcs
  double elapsed_s_ = 0.0;
  double travelled_mm_ = 0.0;
  EmbolusPath path_;
  TransitState state_ = TransitState::kTravelling;
};

// The fragment's whole path and where it lodges in the network's current flows (its transit
// run to the end). An error for a bad fragment or a start with no flow.
[[nodiscard]] base::Result<EmbolusPath> carry_fragment(const FlowNetwork& network, const Fragment& fragment);

// Outlets (indices in terminals) outside `target` whose flow `with_embolus` is lower than
// `without` by more than kHypoperfusedDrop: the new territories an embolus starves.
[[nodiscard]] std::vector<std::size_t> new_territories(const TargetTerritory& target, const std::vector<Terminal>& without,
                                                       const std::vector<Terminal>& with_embolus);

}  // namespace cathbox::flow
