#include "flow/reperfusion.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace cathbox::flow {

std::string_view etici_label(Etici grade) {
  static constexpr std::array<std::string_view, 7> kLabels{"0", "1", "2a", "2b50", "2b67", "2c", "3"};
  return kLabels[static_cast<std::size_t>(grade)];
}

Etici etici_from_fraction(double reperfused_fraction, bool antegrade_past_occlusion) {
  const double f = std::isfinite(reperfused_fraction) ? std::clamp(reperfused_fraction, 0.0, 1.0) : 0.0;
  const long percent = std::lround(100.0 * f);
  if (percent >= 100) return Etici::k3;
  if (percent >= 90) return Etici::k2c;
  if (percent >= 67) return Etici::k2b67;
  if (percent >= 50) return Etici::k2b50;
  if (percent >= 1) return Etici::k2a;
  return antegrade_past_occlusion ? Etici::k1 : Etici::k0;
}

base::Result<TargetTerritory> TargetTerritory::find(const std::vector<Terminal>& open, const std::vector<Terminal>& occluded) {
  if (open.size() != occluded.size()) return base::Error{"reperfusion: the open and occluded networks differ"};
  TargetTerritory t;
  for (std::size_t k = 0; k < open.size(); ++k) {
    if (open[k].role != EndRole::kOutlet || !(open[k].flow_ml_min > 0.0)) continue;
    const double base = open[k].flow_ml_min;
    const double occ = std::max(0.0, occluded[k].flow_ml_min);
    if (base - occ > kHypoperfusedDrop * base) t.outlets_.push_back({k, base, occ});
  }
  if (t.outlets_.empty()) return base::Error{"reperfusion: the occlusion starves no outlet"};
  return t;
}

double TargetTerritory::reperfused_fraction(const std::vector<Terminal>& now) const {
  double weight = 0.0, reperfused = 0.0;
  for (const TerritoryOutlet& o : outlets_) {
    const double q = o.terminal < now.size() ? now[o.terminal].flow_ml_min : 0.0;
    const double share = std::clamp((q - o.occluded_ml_min) / (o.baseline_ml_min - o.occluded_ml_min), 0.0, 1.0);
    reperfused += o.baseline_ml_min * share;
    weight += o.baseline_ml_min;
  }
  return weight > 0.0 ? reperfused / weight : 0.0;
}

}  // namespace cathbox::flow
