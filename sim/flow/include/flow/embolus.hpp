#pragma once
// A clot fragment carried by the blood: from where it breaks off it follows the flow (at each
// junction into the branch that takes the most flow away from it, the likeliest path) until it
// reaches a lumen narrower than itself, where it lodges as a new clot occluding that branch;
// a fragment that reaches an outlet lodges at the outlet's end (beyond the model, in that
// territory). An embolus to a new territory (ENT) is one whose clot starves an outlet outside
// the target territory (reperfusion.hpp).
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
};

// The fragment's path and where it lodges in the network's current flows. An error for a bad
// fragment or a start with no flow.
[[nodiscard]] base::Result<EmbolusPath> carry_fragment(const FlowNetwork& network, const Fragment& fragment);

// Outlets (indices in terminals) outside `target` whose flow `with_embolus` is lower than
// `without` by more than kHypoperfusedDrop: the new territories an embolus starves.
[[nodiscard]] std::vector<std::size_t> new_territories(const TargetTerritory& target, const std::vector<Terminal>& without,
                                                       const std::vector<Terminal>& with_embolus);

}  // namespace cathbox::flow
