#pragma once
// FlowNetwork's terminals (flow_terminals.cpp): the node of each segment end, and each free
// end's role, target flow and inflow from the defaults and the case's settings. Private to
// sim/flow (flow_network.cpp builds the network from them).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "base/result.hpp"
#include "flow/flow_network.hpp"
#include "vessel/vessel_graph.hpp"

namespace cathbox::flow::terminals {

// Node of each segment end: junctions first, then free ends in the graph's order.
class EndNodes {
 public:
  EndNodes(const vessel::VesselGraph& graph, std::size_t n_seg) : graph_(graph), free_end_index_(2 * n_seg, -1) {
    for (std::size_t k = 0; k < graph.free_ends().size(); ++k) {
      const vessel::SegmentEnd& e = graph.free_ends()[k];
      free_end_index_[2 * e.segment + (e.at_end ? 1 : 0)] = static_cast<int>(k);
    }
  }
  [[nodiscard]] std::size_t count() const { return graph_.junctions().size() + graph_.free_ends().size(); }
  [[nodiscard]] int node(std::size_t seg, bool at_end) const {
    const int j = graph_.junction_of(static_cast<std::uint32_t>(seg), at_end);
    return j >= 0 ? j : static_cast<int>(graph_.junctions().size()) + free_end_index_[2 * seg + (at_end ? 1 : 0)];
  }

 private:
  const vessel::VesselGraph& graph_;
  std::vector<int> free_end_index_;
};

// Terminals by name: free starts are inlets, free ends outlets, blind sacs closed.
std::vector<Terminal> default_terminals(const vessel::VesselModel& model, const vessel::VesselGraph& graph, const EndNodes& nodes,
                                        const FlowSettings& set);

// The case's closed ends, outlet targets and inflows override the defaults.
base::Status<> apply_case_terminals(const vessel::VesselModel& model, const FlowSettings& set, std::vector<Terminal>& terminals);

// A component without an inlet takes its widest open free end as one.
void promote_widest_outlet(const vessel::VesselModel& model, std::vector<Terminal>& terminals, const std::vector<std::size_t>& ks);

// Outlet targets: overrides; territories (a side's share split among its outlets by r^3);
// the descending aorta takes the rest of the cardiac output; Murray's law otherwise.
void assign_outlet_targets(const vessel::VesselModel& model, const FlowSettings& set, std::vector<Terminal>& terminals,
                           const std::vector<std::size_t>& ks);

// Inflows: prescribed ones, the rest of the outlets' total shared by r^3.
void assign_inflows(const vessel::VesselModel& model, std::vector<Terminal>& terminals, const std::vector<std::size_t>& ks);

}  // namespace cathbox::flow::terminals
