#pragma once
// Reperfusion of an occluded territory, graded on the expanded TICI scale from the flows of the
// network (Liebeskind et al., J NeuroIntervent Surg 2019: eTICI 2a = 1-49 %, 2b50 = 50-66 %,
// 2b67 = 67-89 %, 2c = 90-99 %, 3 = 100 % of the initially hypoperfused territory reperfused).
//
// - The target territory is the set of outlets whose flow the occlusion lowers by more than
//   kHypoperfusedDrop of their baseline (found by comparing the open and the occluded network),
//   each weighted by its baseline flow (tissue perfused ~ flow).
// - An outlet's reperfusion is (Q_now - Q_occluded) / (Q_baseline - Q_occluded), clamped to
//   [0, 1]: collateral flow counts as no reperfusion, full antegrade flow as complete.
// - The reperfused fraction is the weighted mean, rounded to whole percent for the bands; 0 %
//   is eTICI 1 when flow passes the occlusion site without reaching the territory
//   (antegrade_past_occlusion), else eTICI 0.
#include <cstdint>
#include <string_view>
#include <vector>

#include "base/result.hpp"
#include "flow/flow_network.hpp"

namespace cathbox::flow {

enum class Etici : std::uint8_t { k0, k1, k2a, k2b50, k2b67, k2c, k3 };

inline constexpr double kHypoperfusedDrop = 0.05;

[[nodiscard]] std::string_view etici_label(Etici grade);
// The grade of a reperfused fraction in [0, 1].
[[nodiscard]] Etici etici_from_fraction(double reperfused_fraction, bool antegrade_past_occlusion = false);
// True when `grade` is at least `floor` (e.g. >= 2c for the first-pass effect).
[[nodiscard]] inline bool at_least(Etici grade, Etici floor) { return static_cast<int>(grade) >= static_cast<int>(floor); }

struct TerritoryOutlet {
  std::size_t terminal = 0;      // index in FlowNetwork::terminals()
  double baseline_ml_min = 0.0;
  double occluded_ml_min = 0.0;
};

class TargetTerritory {
 public:
  // From the terminals of the same network solved open and occluded (FlowNetwork::terminals()
  // before and after occlude()). An error when the occlusion starves no outlet.
  [[nodiscard]] static base::Result<TargetTerritory> find(const std::vector<Terminal>& open, const std::vector<Terminal>& occluded);

  [[nodiscard]] const std::vector<TerritoryOutlet>& outlets() const { return outlets_; }
  // Reperfused fraction in [0, 1] for the terminals of the network now.
  [[nodiscard]] double reperfused_fraction(const std::vector<Terminal>& now) const;
  [[nodiscard]] Etici grade(const std::vector<Terminal>& now, bool antegrade_past_occlusion = false) const {
    return etici_from_fraction(reperfused_fraction(now), antegrade_past_occlusion);
  }

 private:
  std::vector<TerritoryOutlet> outlets_;
};

}  // namespace cathbox::flow
