#include "flow/contrast_transport.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "lumen.hpp"

namespace cathbox::flow {
namespace {

constexpr double kFlowNoise = 1e-9;        // flows below this share of the largest are zero
constexpr double kMinCellLength_mm = 0.1;  // volume floor for degenerate (zero-length) segments
constexpr int kMaxSubsteps = 4000;
constexpr double kNegligible_mgI_ml = 1e-30;

// Volume of the truncated cone (r0 -> r1 over length L) from its start to x.
double partial_cone_volume(double r0, double r1, double length_mm, double x_mm) {
  if (length_mm <= 0.0) return 0.0;
  const double dr = (r1 - r0) / length_mm;
  return kPi * (r0 * r0 * x_mm + r0 * dr * x_mm * x_mm + dr * dr * x_mm * x_mm * x_mm / 3.0);
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
    const double mean_r = length > 0.0 ? std::sqrt(f.volume_mm3 / (kPi * length)) : seg.points.front().radius_mm;
    const double cell_len = std::max(options_.cell_length_mm, options_.cell_length_radii * mean_r);
    const int n = std::max(std::max(options_.min_cells, 1), static_cast<int>(std::lround(length / cell_len)));
    s.first = static_cast<std::uint32_t>(conc_.size());
    s.count = static_cast<std::uint32_t>(n);
    s.bounds = static_cast<std::uint32_t>(bounds_.size());
    s.faces = static_cast<std::uint32_t>(gamma_.size());
    const double floor_volume = kPi * f.min_radius_mm * f.min_radius_mm * kMinCellLength_mm;
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

std::pair<int, int> ContrastTransport::injection_entry(const SegmentCells& tip) const {
  if (tip.sac >= 0) return {sacs_[static_cast<std::size_t>(tip.sac)].mouth, 1};
  int dir = 1;
  if (tip.flow_mm3_s < 0.0) dir = -1;
  if (tip.flow_mm3_s == 0.0 && network_->node_pressure_Pa(tip.start_node) < network_->node_pressure_Pa(tip.end_node)) dir = -1;
  int down = dir > 0 ? tip.end_node : tip.start_node;
  if (tip.flow_mm3_s == 0.0) {
    const auto [o, d] = node_outflow_mm3_s(down);
    if (o + d <= 0.0) {
      dir = -dir;
      down = dir > 0 ? tip.end_node : tip.start_node;
    }
  }
  return {down, dir};
}

std::string ContrastTransport::route_injection(std::uint32_t segment, double arc_mm) {
  for (SegmentCells& s : segs_) s.added = 0.0;
  std::fill(node_added_.begin(), node_added_.end(), 0.0);
  const SegmentCells& tip = segs_[segment];
  const auto [down, dir] = injection_entry(tip);
  node_added_[static_cast<std::size_t>(down)] = 1.0;
  for (int node : node_order_) {
    const double a = node_added_[static_cast<std::size_t>(node)];
    if (a <= 0.0) continue;
    const auto [out, drain] = node_outflow_mm3_s(node);
    if (out + drain <= 0.0) return "no blood flow carries contrast away from the catheter tip";
    for (std::uint32_t e = node_first_[static_cast<std::size_t>(node)]; e < node_first_[static_cast<std::size_t>(node) + 1]; ++e) {
      const std::uint32_t si = node_ends_[e] / 2;
      SegmentCells& s = segs_[si];
      const bool at_end = (node_ends_[e] & 1u) != 0;
      const double leaving = at_end ? -s.flow_mm3_s : s.flow_mm3_s;
      if (s.sac >= 0 || leaving <= 0.0) continue;
      const double share = a * leaving / (out + drain);
      s.added += at_end ? -share : share;
      node_added_[static_cast<std::size_t>(at_end ? s.start_node : s.end_node)] += share;
    }
  }
  tip_segment_ = segment;
  tip_dir_ = dir;
  tip_cell_ = 0;
  if (tip.sac < 0) {
    const double* b = bounds_.data() + tip.bounds;
    const auto it = std::upper_bound(b + 1, b + tip.count, arc_mm);
    tip_cell_ = static_cast<std::uint32_t>(it - (b + 1));
  }
  return {};
}

std::string ContrastTransport::inject(const CenterlinePosition& at, const Injection& injection) {
  if (!(std::isfinite(injection.volume_ml) && injection.volume_ml > 0.0 && injection.volume_ml <= 500.0)) {
    return "injection volume must be in (0, 500] mL";
  }
  if (!(std::isfinite(injection.rate_ml_s) && injection.rate_ml_s > 0.0 && injection.rate_ml_s <= 50.0)) {
    return "injection rate must be in (0, 50] mL/s";
  }
  if (!(std::isfinite(injection.concentration_mgI_ml) && injection.concentration_mgI_ml > 0.0 &&
        injection.concentration_mgI_ml <= 1000.0)) {
    return "contrast concentration must be in (0, 1000] mgI/mL";
  }
  if (at.segment >= segs_.size()) return "injection site: no segment " + std::to_string(at.segment);
  const std::int64_t old_tip = tip_segment_;
  const std::uint32_t old_cell = tip_cell_;
  const int old_dir = tip_dir_;
  const std::vector<double> old_added = [&] {
    std::vector<double> v;
    v.reserve(segs_.size());
    for (const SegmentCells& s : segs_) v.push_back(s.added);
    return v;
  }();
  if (std::string e = route_injection(at.segment, at.arc_mm); !e.empty()) {
    tip_segment_ = old_tip;
    tip_cell_ = old_cell;
    tip_dir_ = old_dir;
    for (std::size_t i = 0; i < segs_.size(); ++i) segs_[i].added = old_added[i];
    return e;
  }
  rate_mm3_s_ = injection.rate_ml_s * 1000.0;
  remaining_mm3_ = injection.volume_ml * 1000.0;
  injectate_mgI_ml_ = injection.concentration_mgI_ml;
  update_substeps();
  return {};
}

void ContrastTransport::stop_injection() {
  remaining_mm3_ = 0.0;
  update_substeps();
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

double ContrastTransport::mouth_inflow_mm3_s(int mouth, std::uint32_t sac_segment) const {
  double through = 0.0;  // steady flow entering the mouth from the rest of the network
  const auto m = static_cast<std::size_t>(mouth);
  for (std::uint32_t e = node_first_[m]; e < node_first_[m + 1]; ++e) {
    const std::uint32_t si = node_ends_[e] / 2;
    if (si == sac_segment) continue;
    const double into = (node_ends_[e] & 1u) ? segs_[si].flow_mm3_s : -segs_[si].flow_mm3_s;
    through += std::max(0.0, into);
  }
  return through;
}

void ContrastTransport::refresh_flows() {
  const std::vector<SegmentFlow>& flows = network_->segments();
  double max_flow = 0.0;
  for (const SegmentFlow& f : flows) max_flow = std::max(max_flow, std::abs(f.flow_mm3_s));
  for (std::size_t i = 0; i < segs_.size(); ++i) {
    const double q = flows[i].flow_mm3_s;
    segs_[i].flow_mm3_s = std::abs(q) < kFlowNoise * max_flow ? 0.0 : q;
  }
  for (const Terminal& t : network_->terminals()) {  // a closed end's exchange follows its mouth's inflow
    if (t.role != EndRole::kClosed || segs_[t.segment].sac < 0) continue;
    Sac& sac = sacs_[static_cast<std::size_t>(segs_[t.segment].sac)];
    sac.exchange_mm3_s = t.target_ml_min * mouth_inflow_mm3_s(sac.mouth, t.segment);
  }
  // Decreasing pressure, ties in node order (the constructor's stable sort of 0, 1, 2, ...).
  const FlowNetwork& n = *network_;
  std::sort(node_order_.begin(), node_order_.end(), [&n](int a, int b) {
    const double pa = n.node_pressure_Pa(a);
    const double pb = n.node_pressure_Pa(b);
    return pa > pb || (pa == pb && a < b);
  });
  update_substeps();
}

void ContrastTransport::update_substeps() {
  const double w = network_->max_flow_scale();
  const double q = injecting() ? rate_mm3_s_ : 0.0;
  double rate = 0.0;  // largest (flow through a cell) / (cell volume), 1/s
  for (std::size_t i = 0; i < segs_.size(); ++i) {
    const SegmentCells& s = segs_[i];
    const bool tip = static_cast<std::int64_t>(i) == tip_segment_;
    if (s.sac >= 0) {
      const Sac& sac = sacs_[static_cast<std::size_t>(s.sac)];
      rate = std::max(rate, (w * sac.exchange_mm3_s + (tip ? q : 0.0)) / sac.volume_mm3);
      continue;
    }
    const double f = w * std::abs(s.flow_mm3_s) + q * std::abs(s.added) + (tip ? q : 0.0);
    rate = std::max(rate, f / s.cell_volume_mm3);
  }
  substeps_ = std::clamp(static_cast<int>(std::ceil(options_.step_s * rate - 1e-9)), 1, kMaxSubsteps);
}

void ContrastTransport::step() {
  const double dt = options_.step_s / substeps_;
  const double t0 = time_s();
  double q_sum = 0.0;
  for (int sub = 0; sub < substeps_; ++sub) {
    const double w = network_->flow_scale(t0 + (sub + 0.5) * dt);
    double q = 0.0;
    if (remaining_mm3_ > 0.0) {
      q = std::min(rate_mm3_s_, remaining_mm3_ / dt);
      remaining_mm3_ -= q * dt;
      if (remaining_mm3_ < 1e-9) remaining_mm3_ = 0.0;
      injected_mg_ += injectate_mgI_ml_ * q * dt * 1e-3;
      injected_ml_ += q * dt * 1e-3;
    }
    advect(dt, w, q);
    q_sum += q;
  }
  last_rate_mm3_s_ = q_sum / substeps_;
  diffuse(options_.step_s, network_->flow_scale(t0 + 0.5 * options_.step_s), last_rate_mm3_s_);
  // Washout tails decay geometrically; below 1e-30 mgI/mL they are dropped (no subnormal
  // arithmetic; the iodine so dropped is below 1e-25 mg per cell).
  for (double& c : conc_) c = c < kNegligible_mgI_ml ? 0.0 : c;
  ++steps_;
  if (remaining_mm3_ == 0.0 && tip_segment_ >= 0 && last_rate_mm3_s_ > 0.0) update_substeps();
}

namespace {

// Upwind update of a segment's cells under a uniform flow: k = dt / cell volume, f the flow
// (+ along the segment), the inflowing end's node concentration upstream of the first cell.
void sweep_uniform(double* c, std::uint32_t n, double k, double f, double c_start, double c_end) {
  if (f >= 0.0) {
    double prev = c_start;
    for (std::uint32_t j = 0; j < n; ++j) {
      const double old = c[j];
      c[j] = old + k * f * (prev - old);
      prev = old;
    }
  } else {
    double prev = c_end;
    for (std::uint32_t j = n; j-- > 0;) {
      const double old = c[j];
      c[j] = old - k * f * (prev - old);
      prev = old;
    }
  }
}

}  // namespace

void ContrastTransport::advect(double dt, double w, double q) {
  const std::size_t n_nodes = node_conc_.size();
  double* in = scratch_a_.data();
  double* mass = in + n_nodes;
  double* out = mass + n_nodes;
  std::fill(in, in + 3 * n_nodes, 0.0);
  gather_node_flows(w, q, in, mass, out);
  mix_nodes(dt, in, mass, out);
  for (std::uint32_t i = 0; i < segs_.size(); ++i) {
    const SegmentCells& s = segs_[i];
    if (s.sac >= 0 || static_cast<std::int64_t>(i) == tip_segment_) continue;
    sweep_uniform(conc_.data() + s.first, s.count, dt / s.cell_volume_mm3, w * s.flow_mm3_s + q * s.added,
                  node_conc_[static_cast<std::size_t>(s.start_node)], node_conc_[static_cast<std::size_t>(s.end_node)]);
  }
  if (tip_segment_ >= 0 && segs_[static_cast<std::size_t>(tip_segment_)].sac < 0) sweep_tip_segment(dt, w, q);
  mix_sacs(dt, w, q);
}

// What each node receives from its segments (old concentrations) and sends into them.
void ContrastTransport::gather_node_flows(double w, double q, double* in, double* mass, double* out) const {
  for (std::uint32_t i = 0; i < segs_.size(); ++i) {
    const SegmentCells& s = segs_[i];
    if (s.sac >= 0) continue;
    const double f0 = face_flow(s, i, 0, w, q);
    const double fn = face_flow(s, i, s.count, w, q);
    const auto a = static_cast<std::size_t>(s.start_node);
    const auto b = static_cast<std::size_t>(s.end_node);
    if (f0 < 0.0) {
      in[a] -= f0;
      mass[a] -= f0 * conc_[s.first];
    } else {
      out[a] += f0;
    }
    if (fn > 0.0) {
      in[b] += fn;
      mass[b] += fn * conc_[s.first + s.count - 1];
    } else {
      out[b] -= fn;
    }
  }
  for (const Sac& sac : sacs_) {
    const auto m = static_cast<std::size_t>(sac.mouth);
    const double back = w * sac.exchange_mm3_s + (tip_segment_ == sac.segment ? q : 0.0);
    in[m] += back;
    mass[m] += back * conc_[segs_[sac.segment].first];
    out[m] += w * sac.exchange_mm3_s;
  }
}

// Each node's mixed concentration; outlets drain what their segments do not carry away.
void ContrastTransport::mix_nodes(double dt, const double* in, const double* mass, const double* out) {
  for (std::size_t n = 0; n < node_conc_.size(); ++n) {
    double o = out[n];
    double drain = 0.0;
    if (node_kind_[n] == NodeKind::kOutlet) {
      drain = std::max(0.0, in[n] - o);
      o += drain;
    }
    // An inlet's own inflow carries no contrast: it only dilutes.
    node_conc_[n] = o > 0.0 ? mass[n] / o : 0.0;
    if (o <= 0.0 && mass[n] > 0.0) stalled_mg_ += mass[n] * dt * 1e-3;
    washed_mg_ += drain * node_conc_[n] * dt * 1e-3;
  }
}

// The tip's segment: the flow changes at the tip cell, which also receives the injectate.
void ContrastTransport::sweep_tip_segment(double dt, double w, double q) {
  const auto i = static_cast<std::uint32_t>(tip_segment_);
  const SegmentCells& s = segs_[i];
  double* c = conc_.data() + s.first;
  const double k = dt / s.cell_volume_mm3;
  const double c_start = node_conc_[static_cast<std::size_t>(s.start_node)];
  const double c_end = node_conc_[static_cast<std::size_t>(s.end_node)];
  const std::uint32_t n = s.count;
  const auto flux = [&](std::uint32_t face, double left_c, double right_c) {
    const double f = face_flow(s, i, face, w, q);
    return f > 0.0 ? f * left_c : f * right_c;
  };
  double left = flux(0, c_start, c[0]);
  for (std::uint32_t j = 0; j < n; ++j) {
    const double right = flux(j + 1, c[j], j + 1 < n ? c[j + 1] : c_end);
    c[j] += k * (left - right);
    if (j == tip_cell_) c[j] += k * q * injectate_mgI_ml_;
    left = right;
  }
}

// Blind sacs: well mixed, exchanging with their mouth.
void ContrastTransport::mix_sacs(double dt, double w, double q) {
  for (const Sac& sac : sacs_) {
    const SegmentCells& s = segs_[sac.segment];
    const double c_old = conc_[s.first];
    const double ex = w * sac.exchange_mm3_s;
    const double qi = tip_segment_ == sac.segment ? q : 0.0;
    const double c_new =
        c_old + dt / sac.volume_mm3 * (ex * (node_conc_[static_cast<std::size_t>(sac.mouth)] - c_old) + qi * (injectate_mgI_ml_ - c_old));
    std::fill(conc_.begin() + s.first, conc_.begin() + s.first + s.count, c_new);
  }
}

void ContrastTransport::diffuse(double dt, double w, double q) {
  if (network_->settings().dispersion_radii <= 0.0) return;
  const double dt_sub = options_.step_s / substeps_;
  double* e = scratch_b_.data();    // e[f]: coupling of face f (1..n-1), dt g / V
  double* cp = scratch_c_.data();   // Thomas: modified upper diagonal
  for (std::uint32_t i = 0; i < segs_.size(); ++i) {
    const SegmentCells& s = segs_[i];
    if (s.sac >= 0 || s.count < 2) continue;
    const double v = s.cell_volume_mm3;
    bool any = false;
    for (std::uint32_t f = 1; f < s.count; ++f) {
      const double flow = std::abs(face_flow(s, i, f, w, q));
      const double courant = flow * dt_sub / v;
      const double g = flow * std::max(0.0, gamma_[s.faces + f - 1] - 0.5 * (1.0 - courant));
      e[f] = dt * g / v;
      any = any || e[f] > 0.0;
    }
    if (!any) continue;
    e[0] = 0.0;
    e[s.count] = 0.0;
    // (1 + e_j + e_{j+1}) c_j - e_j c_{j-1} - e_{j+1} c_{j+1} = c_j(old): Thomas algorithm.
    double* c = conc_.data() + s.first;
    double denom = 1.0 + e[1];
    cp[0] = -e[1] / denom;
    c[0] = c[0] / denom;
    for (std::uint32_t j = 1; j < s.count; ++j) {
      const double diag = 1.0 + e[j] + e[j + 1];
      denom = diag + e[j] * cp[j - 1];
      cp[j] = -e[j + 1] / denom;
      c[j] = (c[j] + e[j] * c[j - 1]) / denom;
    }
    for (std::uint32_t j = s.count - 1; j-- > 0;) c[j] -= cp[j] * c[j + 1];
  }
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
