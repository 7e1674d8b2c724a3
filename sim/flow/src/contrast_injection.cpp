// ContrastTransport's injection: where the tip's injectate enters the cells, and starting and
// stopping it.
#include "flow/contrast_transport.hpp"

#include <algorithm>
#include <cmath>

namespace cathbox::flow {

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

}  // namespace cathbox::flow
