#pragma once
// Iodinated contrast carried by the blood flow (FlowNetwork), for angiography.
//
// - Each segment is cut into cells of equal lumen volume (so the Courant number is the same
//   along a segment even through a stenosis), at least max(cell_length_mm, cell_length_radii *
//   mean radius) long. The state is the iodine concentration per cell, mgI/mL.
// - Advection: first-order upwind finite volumes in flux form, explicit, with as many equal
//   substeps per step as keep every cell's Courant number <= 1 (so concentrations stay within
//   the range of their sources). Junctions hold no volume: the concentration leaving a node is
//   the flux-weighted mix of what enters it (mass in / flow out), so the contrast splits at
//   junctions by flow and mass is conserved exactly; outlets wash it out; inlets bring blood
//   without contrast.
// - Dispersion: within segments, D = k r |v| (k = FlowSettings::dispersion_radii), less the
//   upwind scheme's own numerical diffusion |v| dx (1 - C) / 2, applied once per step by an
//   implicit (backward Euler) solve with no flux through segment ends. Contrast therefore
//   moves upstream only within a segment and never crosses a junction against the flow.
// - Injection at a centreline position (the catheter tip): the injected volume flow q is
//   added to the flow from the tip downstream, split at each junction like the blood flow
//   there, so the tip's cell mixes q of contrast at the injectate's concentration with the
//   local blood flow (c = c0 q / (Q + q) in steady state) and the added volume leaves through
//   the outlets the tip's blood goes to.
// - Blind sacs (closed ends, e.g. an aneurysm) are well mixed and exchange
//   FlowSettings::sac_exchange_fraction of their junction's through-flow with it.
// - Fixed step (default 10 ms, 100 Hz), fixed order of operations, no allocation per step:
//   the same calls give the same numbers.
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "flow/centerline_locator.hpp"
#include "flow/flow_network.hpp"

namespace cathbox::flow {

struct TransportOptions {
  double step_s = 0.01;             // one step() advances this much (100 Hz)
  double cell_length_mm = 1.0;      // shortest cell
  double cell_length_radii = 0.5;   // cells are at least this many mean radii long
  int min_cells = 2;                // per segment
};

struct Injection {
  double volume_ml = 6.0;
  double rate_ml_s = 3.0;
  double concentration_mgI_ml = 300.0;  // e.g. iohexol 300
};

class ContrastTransport {
 public:
  // Keeps a reference to the network, which must outlive the transport.
  explicit ContrastTransport(const FlowNetwork& network, const TransportOptions& options = {});

  // Starts an injection at a centreline position; a running one is replaced. Returns an
  // error (and changes nothing) for values out of range or when no flow leaves the tip.
  [[nodiscard]] std::string inject(const CenterlinePosition& at, const Injection& injection);
  // The nearest centreline position to a point (e.g. the catheter tip).
  [[nodiscard]] CenterlinePosition locate(const glm::dvec3& point_mm) const { return locator_.nearest(point_mm); }
  void stop_injection();
  // Advances one fixed step.
  void step();
  // Removes all contrast (the time and the running totals restart at zero).
  void reset();
  // The network was solved again (FlowNetwork::occlude: a clot removed, a balloon inflated):
  // takes its flows from the next step; the contrast stays where it is. A running injection
  // keeps the path it was given when it started. No allocation.
  void refresh_flows();

  [[nodiscard]] double time_s() const { return static_cast<double>(steps_) * options_.step_s; }
  [[nodiscard]] bool injecting() const { return remaining_mm3_ > 0.0; }
  [[nodiscard]] const TransportOptions& options() const { return options_; }
  [[nodiscard]] const FlowNetwork& network() const { return *network_; }
  [[nodiscard]] const CenterlineLocator& locator() const { return locator_; }

  // Concentration (mgI/mL) on a segment's centreline, linear between cell centres.
  [[nodiscard]] double concentration(std::uint32_t segment, double arc_mm) const;
  // Concentration leaving a junction (index in vessel::VesselGraph::junctions()) at the last substep.
  [[nodiscard]] double junction_concentration(int junction) const;
  // Highest cell concentration of a segment.
  [[nodiscard]] double max_concentration(std::uint32_t segment) const;
  [[nodiscard]] std::span<const double> cell_concentrations(std::uint32_t segment) const;
  // The n + 1 cell boundaries of a segment, as arc lengths (mm) from its first point.
  [[nodiscard]] std::span<const double> cell_bounds_mm(std::uint32_t segment) const;
  [[nodiscard]] std::size_t cell_count() const { return conc_.size(); }
  [[nodiscard]] int substeps() const { return substeps_; }

  // Iodine bookkeeping, mg: injected so far, in the vessels now, washed out through outlets.
  [[nodiscard]] double injected_mg() const { return injected_mg_; }
  [[nodiscard]] double in_vessels_mg() const;
  [[nodiscard]] double washed_out_mg() const { return washed_mg_; }
  [[nodiscard]] double injected_volume_ml() const { return injected_ml_; }
  // Mass that reached a node with no way out (never expected; tests check it stays 0).
  [[nodiscard]] double stalled_mg() const { return stalled_mg_; }

 private:
  struct SegmentCells {
    std::uint32_t first = 0;    // first cell in conc_
    std::uint32_t count = 0;
    std::uint32_t bounds = 0;   // first boundary in bounds_ (count + 1 of them)
    std::uint32_t faces = 0;    // first internal face in gamma_ (count - 1 of them)
    double cell_volume_mm3 = 0.0;
    double flow_mm3_s = 0.0;    // steady flow (tiny solver residues cleared), + along the segment
    double added = 0.0;         // injection flow per unit injection rate (signed), uniform
    int start_node = -1;
    int end_node = -1;
    int sac = -1;               // index in sacs_ when this segment is a blind sac
  };
  struct Sac {
    std::uint32_t segment = 0;
    int mouth = -1;             // node where it opens
    double volume_mm3 = 0.0;
    double exchange_mm3_s = 0.0;  // steady exchange flow
  };
  enum class NodeKind : std::uint8_t { kJunction, kInlet, kOutlet, kDead };

  [[nodiscard]] double face_flow(const SegmentCells& s, std::uint32_t segment, std::uint32_t face, double w, double q) const;
  // Steady flow entering node `mouth` from every segment but the sac's.
  [[nodiscard]] double mouth_inflow_mm3_s(int mouth, std::uint32_t sac_segment) const;
  // Flow leaving `node` through its segments and, at an outlet, its drain: {out, drain}.
  [[nodiscard]] std::pair<double, double> node_outflow_mm3_s(int node) const;
  // The node contrast from the tip at `tip` first reaches, with the tip's flow direction.
  [[nodiscard]] std::pair<int, int> injection_entry(const SegmentCells& tip) const;
  [[nodiscard]] std::string route_injection(std::uint32_t segment, double arc_mm);
  void update_substeps();
  // One upwind substep: gather the segment ends into the nodes, mix them, sweep the segments
  // (the tip's with its injection), mix the blind sacs.
  void advect(double dt, double w, double q);
  void gather_node_flows(double w, double q, double* in, double* mass, double* out) const;
  void mix_nodes(double dt, const double* in, const double* mass, const double* out);
  void sweep_tip_segment(double dt, double w, double q);
  void mix_sacs(double dt, double w, double q);
  void diffuse(double dt, double w, double q);

  const FlowNetwork* network_;
  TransportOptions options_;
  CenterlineLocator locator_;
  std::vector<SegmentCells> segs_;
  std::vector<double> conc_;        // per cell
  std::vector<double> bounds_;      // cell boundaries (arc mm), per segment
  std::vector<double> gamma_;       // per internal face: k r / dx
  std::vector<Sac> sacs_;
  std::vector<NodeKind> node_kind_;
  std::vector<std::uint32_t> node_first_;  // CSR: ends at each node
  std::vector<std::uint32_t> node_ends_;   // segment * 2 + (at_end ? 1 : 0)
  std::vector<int> node_sac_;              // sac opening at a node, or -1
  std::vector<int> node_order_;            // nodes by decreasing pressure
  std::vector<double> node_conc_;
  std::vector<double> node_added_;         // scratch for routing
  std::vector<double> scratch_a_, scratch_b_, scratch_c_;  // tridiagonal solve

  int substeps_ = 1;
  std::int64_t steps_ = 0;
  // The running injection.
  std::int64_t tip_segment_ = -1;
  std::uint32_t tip_cell_ = 0;
  int tip_dir_ = 1;
  double rate_mm3_s_ = 0.0;
  double remaining_mm3_ = 0.0;
  double injectate_mgI_ml_ = 0.0;
  double last_rate_mm3_s_ = 0.0;

  double injected_mg_ = 0.0;
  double injected_ml_ = 0.0;
  double washed_mg_ = 0.0;
  double stalled_mg_ = 0.0;
};

}  // namespace cathbox::flow
