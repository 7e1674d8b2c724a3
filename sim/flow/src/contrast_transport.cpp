// ContrastTransport's cells (construction, each segment cut into cells of equal lumen volume)
// and what it answers about them. Injection: contrast_injection.cpp; the time step (advection,
// node mixing, sacs, dispersion): contrast_transport_step.cpp.
#include "flow/contrast_transport.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "lumen.hpp"
#include "contrast_transport_internal.hpp"

namespace cathbox::flow {
namespace {

using contrast_detail::kFlowNoise;
constexpr double kMinCellLength_mm = 0.1;  // volume floor for degenerate (zero-length) segments

// Volume of the truncated cone (r0 -> r1 over length L) from its start to x.
double partial_cone_volume(double r0, double r1, double length_mm, double x_mm) {
  if (length_mm <= 0.0) return 0.0;
  const double dr = (r1 - r0) / length_mm;
  return std::numbers::pi * (r0 * r0 * x_mm + r0 * dr * x_mm * x_mm + dr * dr * x_mm * x_mm * x_mm / 3.0);
}

// Arc lengths of n + 1 boundaries cutting a segment into n cells of equal lumen volume.
std::vector<double> equal_volume_bounds(const vessel::Segment& s, const std::vector<double>& arcs, int n) {
  std::vector<double> cumulative(s.points.size(), 0.0);
  for (std::size_t j = 1; j < s.points.size(); ++j) {
    cumulative[j] = cumulative[j - 1] + cone_volume_mm3(s.points[j - 1].radius_mm, s.points[j].radius_mm, arcs[j] - arcs[j - 1]);
  }
  const double total = cumulative.back();
  std::vector<double> bounds(static_cast<std::size_t>(n) + 1, 0.0);
  bounds.back() = arcs.back();
  std::size_t j = 0;
  for (int k = 1; k < n; ++k) {
    const double target = total * k / n;
    while (j + 2 < cumulative.size() && cumulative[j + 1] < target) ++j;
    const double r0 = s.points[j].radius_mm, r1 = s.points[j + 1].radius_mm, len = arcs[j + 1] - arcs[j];
    double lo = 0.0, hi = len;
    for (int it = 0; it < 60; ++it) {
      const double mid = 0.5 * (lo + hi);
      (cumulative[j] + partial_cone_volume(r0, r1, len, mid) < target ? lo : hi) = mid;
    }
    bounds[static_cast<std::size_t>(k)] = std::max(bounds[static_cast<std::size_t>(k) - 1], arcs[j] + 0.5 * (lo + hi));
  }
  return bounds;
}

}  // namespace

ContrastTransport::ContrastTransport(const FlowNetwork& network, const TransportOptions& options)
    : network_(&network), options_(options), locator_(network.model()) {
  const vessel::VesselModel& model = network.model();
  const std::vector<SegmentFlow>& flows = network.segments();
  const double k = network.settings().dispersion_radii;
  double max_flow = 0.0;
  for (const SegmentFlow& f : flows) max_flow = std::max(max_flow, std::abs(f.flow_mm3_s));

  segs_.resize(model.segments.size());
  for (std::size_t i = 0; i < model.segments.size(); ++i) {
    const vessel::Segment& seg = model.segments[i];
    const SegmentFlow& f = flows[i];
    SegmentCells& s = segs_[i];
    const std::vector<double> arcs = point_arcs_mm(seg);
    const double length = arcs.back();
    const double mean_r = length > 0.0 ? std::sqrt(f.volume_mm3 / (std::numbers::pi * length)) : seg.points.front().radius_mm;
    const double cell_len = std::max(options_.cell_length_mm, options_.cell_length_radii * mean_r);
    const int n = std::max(std::max(options_.min_cells, 1), static_cast<int>(std::lround(length / cell_len)));
    s.first = static_cast<std::uint32_t>(conc_.size());
    s.count = static_cast<std::uint32_t>(n);
    s.bounds = static_cast<std::uint32_t>(bounds_.size());
    s.faces = static_cast<std::uint32_t>(gamma_.size());
    const double floor_volume = std::numbers::pi * f.min_radius_mm * f.min_radius_mm * kMinCellLength_mm;
    s.cell_volume_mm3 = std::max(f.volume_mm3 / n, floor_volume);
    s.flow_mm3_s = std::abs(f.flow_mm3_s) < kFlowNoise * max_flow ? 0.0 : f.flow_mm3_s;
    s.start_node = f.start_node;
    s.end_node = f.end_node;
    const std::vector<double> b = equal_volume_bounds(seg, arcs, n);
    bounds_.insert(bounds_.end(), b.begin(), b.end());
    for (int face = 1; face < n; ++face) {
      const auto fu = static_cast<std::size_t>(face);
      const double dx = std::max(0.5 * (b[fu + 1] - b[fu - 1]), 1e-6);
      gamma_.push_back(k * radius_at_mm(seg, arcs, b[fu]) / dx);
    }
    conc_.resize(conc_.size() + static_cast<std::size_t>(n), 0.0);
  }

  // Nodes: the ends meeting at each, their kind, and an order of decreasing pressure.
  const std::size_t n_nodes = network.node_count();
  node_kind_.assign(n_nodes, NodeKind::kJunction);
  std::vector<std::vector<std::uint32_t>> ends(n_nodes);
  for (std::size_t i = 0; i < segs_.size(); ++i) {
    ends[static_cast<std::size_t>(segs_[i].start_node)].push_back(static_cast<std::uint32_t>(2 * i));
    ends[static_cast<std::size_t>(segs_[i].end_node)].push_back(static_cast<std::uint32_t>(2 * i + 1));
  }
  node_first_.push_back(0);
  for (const auto& e : ends) {
    node_ends_.insert(node_ends_.end(), e.begin(), e.end());
    node_first_.push_back(static_cast<std::uint32_t>(node_ends_.size()));
  }
  for (const Terminal& t : network.terminals()) {
    const auto node = static_cast<std::size_t>(t.node);
    if (t.role == EndRole::kInlet) node_kind_[node] = NodeKind::kInlet;
    if (t.role == EndRole::kOutlet) node_kind_[node] = NodeKind::kOutlet;
    if (t.role != EndRole::kClosed) continue;
    node_kind_[node] = NodeKind::kDead;
    Sac sac;
    sac.segment = t.segment;
    sac.mouth = segs_[t.segment].start_node;
    sac.volume_mm3 = segs_[t.segment].cell_volume_mm3 * segs_[t.segment].count;
    sac.exchange_mm3_s = t.target_ml_min * mouth_inflow_mm3_s(sac.mouth, t.segment);
    segs_[t.segment].sac = static_cast<int>(sacs_.size());
    sacs_.push_back(sac);
  }
  node_order_.resize(n_nodes);
  std::iota(node_order_.begin(), node_order_.end(), 0);
  std::stable_sort(node_order_.begin(), node_order_.end(),
                   [&](int a, int b) { return network.node_pressure_Pa(a) > network.node_pressure_Pa(b); });
  node_conc_.assign(n_nodes, 0.0);
  node_added_.assign(n_nodes, 0.0);
  std::uint32_t longest = 1;
  for (const SegmentCells& s : segs_) longest = std::max(longest, s.count);
  scratch_a_.assign(3 * n_nodes + longest, 0.0);
  scratch_b_.assign(longest + 1, 0.0);
  scratch_c_.assign(longest, 0.0);
  update_substeps();
}

double ContrastTransport::face_flow(const SegmentCells& s, std::uint32_t segment, std::uint32_t face, double w, double q) const {
  double f = w * s.flow_mm3_s + q * s.added;
  if (static_cast<std::int64_t>(segment) == tip_segment_ && s.sac < 0) {
    if (tip_dir_ > 0 ? face > tip_cell_ : face <= tip_cell_) f += tip_dir_ * q;
  }
  return f;
}

std::pair<double, double> ContrastTransport::node_outflow_mm3_s(int node) const {
  double in = 0.0, out = 0.0;
  for (std::uint32_t e = node_first_[static_cast<std::size_t>(node)]; e < node_first_[static_cast<std::size_t>(node) + 1]; ++e) {
    const SegmentCells& s = segs_[node_ends_[e] / 2];
    if (s.sac >= 0) continue;
    const double into = (node_ends_[e] & 1u) ? s.flow_mm3_s : -s.flow_mm3_s;
    (into > 0.0 ? in : out) += std::abs(into);
  }
  const bool outlet = node_kind_[static_cast<std::size_t>(node)] == NodeKind::kOutlet;
  return {out, outlet ? std::max(0.0, in - out) : 0.0};
}

void ContrastTransport::reset() {
  std::fill(conc_.begin(), conc_.end(), 0.0);
  std::fill(node_conc_.begin(), node_conc_.end(), 0.0);
  remaining_mm3_ = 0.0;
  steps_ = 0;
  injected_mg_ = injected_ml_ = washed_mg_ = stalled_mg_ = 0.0;
  last_rate_mm3_s_ = 0.0;
  update_substeps();
}

double ContrastTransport::in_vessels_mg() const {
  double m = 0.0;
  for (const SegmentCells& s : segs_) {
    double sum = 0.0;
    for (std::uint32_t j = 0; j < s.count; ++j) sum += conc_[s.first + j];
    m += sum * s.cell_volume_mm3;
  }
  return m * 1e-3;
}

double ContrastTransport::concentration(std::uint32_t segment, double arc_mm) const {
  const SegmentCells& s = segs_[segment];
  const double* c = conc_.data() + s.first;
  const double* b = bounds_.data() + s.bounds;
  const double first_mid = 0.5 * (b[0] + b[1]);
  if (arc_mm <= first_mid || s.count == 1) return c[0];
  const double last_mid = 0.5 * (b[s.count - 1] + b[s.count]);
  if (arc_mm >= last_mid) return c[s.count - 1];
  // Cell j holds arc: the centres j and j+1 bracket it from one side or the other.
  const auto it = std::upper_bound(b + 1, b + s.count, arc_mm);
  std::uint32_t j = static_cast<std::uint32_t>(it - (b + 1));
  const double mid_j = 0.5 * (b[j] + b[j + 1]);
  if (arc_mm < mid_j) --j;
  const double m0 = 0.5 * (b[j] + b[j + 1]);
  const double m1 = 0.5 * (b[j + 1] + b[j + 2]);
  const double t = m1 > m0 ? (arc_mm - m0) / (m1 - m0) : 0.0;
  return c[j] + t * (c[j + 1] - c[j]);
}

double ContrastTransport::junction_concentration(int junction) const { return node_conc_[static_cast<std::size_t>(junction)]; }

double ContrastTransport::max_concentration(std::uint32_t segment) const {
  const SegmentCells& s = segs_[segment];
  return *std::max_element(conc_.begin() + s.first, conc_.begin() + s.first + s.count);
}

std::span<const double> ContrastTransport::cell_concentrations(std::uint32_t segment) const {
  const SegmentCells& s = segs_[segment];
  return {conc_.data() + s.first, s.count};
}

std::span<const double> ContrastTransport::cell_bounds_mm(std::uint32_t segment) const {
  const SegmentCells& s = segs_[segment];
  return {bounds_.data() + s.bounds, s.count + 1u};
}

}  // namespace cathbox::flow
