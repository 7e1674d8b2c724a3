// ContrastTransport's time step: the flows refreshed from the network, sub-steps for stability,
// upwind advection along the segments, mixing at the nodes and in blind sacs, dispersion.
#include "flow/contrast_transport.hpp"

#include <algorithm>
#include <cmath>

#include "contrast_transport_internal.hpp"

namespace cathbox::flow {
namespace {

using contrast_detail::kFlowNoise;
constexpr int kMaxSubsteps = 4000;
constexpr double kNegligible_mgI_ml = 1e-30;

}  // namespace

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

}  // namespace cathbox::flow
